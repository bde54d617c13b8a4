#pragma once
/// An enum's values with the names the user writes (command line, JSON, menus):
/// a name is parsed into the enum once, at the edge, and code deeper in compares
/// enums, never strings.

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace accelviz {

template <class Enum, size_t N>
struct EnumNames {
    std::array<std::pair<Enum, std::string_view>, N> entries;

    constexpr std::string_view name(Enum value) const {
        for (const auto& [e, n] : entries)
            if (e == value) return n;
        return "?";
    }
    constexpr std::optional<Enum> parse(std::string_view text) const {
        for (const auto& [e, n] : entries)
            if (n == text) return e;
        return std::nullopt;
    }
    /// All names, in the table's order (the order menus list them in).
    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const auto& entry : entries) out.emplace_back(entry.second);
        return out;
    }
    /// "a, b or c", for error messages.
    std::string listed() const {
        std::string out;
        for (size_t i = 0; i < N; ++i) {
            if (i > 0) out += i + 1 == N ? " or " : ", ";
            out += '"';
            out += entries[i].second;
            out += '"';
        }
        return out;
    }
};

}  // namespace accelviz

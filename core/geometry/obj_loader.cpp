// load_obj: Wavefront OBJ through tinyobjloader, with a validation pass of our own
// in front of it.
//
// Why two passes? tinyobjloader reads numbers leniently (a bad number becomes 0),
// skips faces with fewer than 3 vertices with a warning, and reports a bad index
// at best as "line N" of the whole file after the fact. The lecture tool must say
// exactly what is wrong and where, so scan_obj() walks the text once, looking at
// `v` and `f` lines only, and stops at the first problem with "PATH:LINE: reason".
// Only text that passed the scan reaches tinyobjloader, which then cannot fail on
// anything we care about; its result is checked once more before use, so a
// disagreement between the two parsers is an error message, never a crash.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string_view>
#include <system_error>

#include "core/geometry/scene.h"

namespace accelviz {

namespace {

/// "PATH:LINE: reason", or "PATH: reason" when no line applies (line == 0).
Error located_error(const std::string& path, size_t line, const std::string& reason) {
    if (line == 0) return Error{path + ": " + reason};
    return Error{path + ":" + std::to_string(line) + ": " + reason};
}

/// The whole file as bytes. Errors: missing, a directory, unreadable.
Expected<std::string> read_whole_file(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) return located_error(path, 0, "no such file");
    if (std::filesystem::is_directory(status)) return located_error(path, 0, "is a directory, not an OBJ file");

    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) return located_error(path, 0, std::string("cannot open: ") + std::strerror(errno));
    std::string bytes;
    char buffer[1 << 16];
    size_t got = 0;
    while ((got = std::fread(buffer, 1, sizeof buffer, file)) > 0) bytes.append(buffer, got);
    const bool failed = std::ferror(file) != 0;
    const int read_errno = errno;
    std::fclose(file);
    if (failed) return located_error(path, 0, std::string("cannot read: ") + std::strerror(read_errno));
    return bytes;
}

bool is_blank(char c) { return c == ' ' || c == '\t'; }

/// Splits a line's body into blank-separated words.
/// Calls `word(std::string_view)` for each; stops early if it returns false.
template <class Fn>
bool for_each_word(std::string_view body, Fn&& word) {
    size_t i = 0;
    while (i < body.size()) {
        while (i < body.size() && is_blank(body[i])) ++i;
        if (i == body.size()) break;
        const size_t start = i;
        while (i < body.size() && !is_blank(body[i])) ++i;
        if (!word(body.substr(start, i - start))) return false;
    }
    return true;
}

/// A whole word as an integer (optional sign). False if anything is left over.
bool parse_integer(std::string_view word, long long& out) {
    if (!word.empty() && word[0] == '+') word.remove_prefix(1);
    if (word.empty()) return false;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), out);
    return ec == std::errc() && end == word.data() + word.size();
}

/// A whole word as a number (optional sign, decimal or exponent form; also
/// "inf"/"nan", which the caller rejects as non-finite).
bool parse_number(std::string_view word, double& out) {
    if (!word.empty() && word[0] == '+') word.remove_prefix(1);
    if (word.empty()) return false;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), out);
    if (ec == std::errc::result_out_of_range) {
        out = std::numeric_limits<double>::infinity();  // e.g. 1e999: reported as too large
        return end == word.data() + word.size();
    }
    return ec == std::errc() && end == word.data() + word.size();
}

std::string quoted(std::string_view word) {
    constexpr size_t kMaxShown = 40;  // keep the message on one short line
    std::string out(1, '\'');
    out.append(word.substr(0, kMaxShown));
    out.append(word.size() > kMaxShown ? "...'" : "'");
    return out;
}

/// The reason a `v` line's body is wrong (empty: it is right): x, y and z must be
/// finite floats; an optional w or vertex colour only has to be a number.
std::string check_vertex(std::string_view body) {
    int count = 0;
    std::string bad;
    for_each_word(body, [&](std::string_view word) {
        double value = 0;
        if (!parse_number(word, value)) {
            bad = "bad number " + quoted(word) + " in vertex";
            return false;
        }
        if (count < 3 && !(std::abs(value) <= double(std::numeric_limits<float>::max()))) {
            bad = "non-finite coordinate " + quoted(word) + " (beyond float range or inf/nan)";
            return false;
        }
        if (count < 3 && std::abs(value) > kMaxCoordinate) {
            char limit[32];
            std::snprintf(limit, sizeof limit, "%g", kMaxCoordinate);
            bad = "coordinate " + quoted(word) + " is beyond +-" + limit +
                  ", where the float ray-triangle test overflows (scale the scene down)";
            return false;
        }
        ++count;
        return true;
    });
    if (bad.empty() && count < 3)
        bad = "vertex has " + std::to_string(count) + " coordinate" + (count == 1 ? "" : "s") + ", needs x y z";
    return bad;
}

/// The reason an `f` line's body is wrong (empty: it is right), its words being
/// "v", "v/vt", "v//vn" or "v/vt/vn" with `defined` vertices before the line;
/// `corners` counts them. A positive index beyond `defined` (a vertex defined
/// later, perhaps) goes to `forward_index` to be judged at the end of the file.
template <class ForwardIndex>
std::string check_face(std::string_view body, size_t vertices_before, size_t& corners, ForwardIndex&& forward_index) {
    const auto defined = static_cast<long long>(vertices_before);
    std::string bad;
    for_each_word(body, [&](std::string_view word) {
        const size_t slash = word.find('/');
        long long index = 0;
        if (!parse_integer(word.substr(0, slash), index)) {
            bad = "bad face index " + quoted(word) + " (want an integer, optionally /vt/vn)";
            return false;
        }
        // Texture and normal indices are ignored, but tinyobjloader rejects 0 or text there.
        for (size_t at = slash; at != std::string_view::npos;) {
            const size_t next = word.find('/', at + 1);
            const std::string_view part = word.substr(at + 1, next == std::string_view::npos ? next : next - at - 1);
            long long other = 0;
            if (!part.empty() && (!parse_integer(part, other) || other == 0)) {
                bad = "bad texture/normal index in " + quoted(word);
                return false;
            }
            at = next;
        }
        if (index == 0) {
            bad = "face index 0 is invalid (OBJ indices start at 1)";
            return false;
        }
        if (index < 0 && defined + index < 0) {
            bad = "face index " + std::to_string(index) + " out of range (only " + std::to_string(defined) +
                  " vertices before this line)";
            return false;
        }
        if (index > defined) forward_index(index);
        ++corners;
        return true;
    });
    if (bad.empty() && corners < 3)
        bad = "face has " + std::to_string(corners) + (corners == 1 ? " vertex" : " vertices") + ", needs at least 3";
    return bad;
}

/// What the scan found in a file that passed it.
struct ObjScan {
    size_t vertex_count = 0;    ///< `v` lines
    size_t triangle_count = 0;  ///< after fan triangulation
};

/// The validation pass over `v` and `f` lines. Lines end at "\n", "\r\n" or a lone
/// "\r", as in tinyobjloader, so both count vertices alike (relative indices
/// depend on that count). It also blanks out a comment at the end of a `v` or `f`
/// line ("f 1 2 3 # top"), which tinyobjloader would read as one more index.
Expected<ObjScan> scan_obj(std::string& text, const std::string& path) {
    ObjScan scan;
    // A positive index may point forward (to a vertex defined later in the file),
    // so it can only be judged at the end. Remembered: each index larger than every
    // vertex count so far and every index remembered before. The earliest line with
    // an index beyond the final count is then the first such entry (the list is
    // increasing), which keeps the list short.
    struct ForwardIndex {
        size_t line;
        long long index;
    };
    std::vector<ForwardIndex> forward;
    long long forward_max = 0;

    size_t line_number = 0;
    size_t error_line = 0;  // the first error found on the way (0: none)
    std::string error_reason;

    size_t pos = 0;
    while (pos < text.size()) {
        // One line: [pos, line_end), then skip its terminator.
        size_t line_end = pos;
        while (line_end < text.size() && text[line_end] != '\n' && text[line_end] != '\r') ++line_end;
        std::string_view line = std::string_view(text).substr(pos, line_end - pos);  // a view, not a copy
        pos = line_end;
        if (pos < text.size()) pos += (text[pos] == '\r' && pos + 1 < text.size() && text[pos + 1] == '\n') ? 2 : 1;
        ++line_number;

        size_t start = 0;
        while (start < line.size() && is_blank(line[start])) ++start;
        line.remove_prefix(start);
        if (line.empty()) continue;
        const bool is_vertex = line[0] == 'v' && (line.size() == 1 || is_blank(line[1]));
        const bool is_face = line[0] == 'f' && (line.size() == 1 || is_blank(line[1]));
        // "v1 2 3" or "f1 2 3": no OBJ statement starts so; read as one it would
        // silently shift every later vertex index, so it is an error.
        if ((line[0] == 'v' || line[0] == 'f') && line.size() > 1 &&
            (std::isdigit(static_cast<unsigned char>(line[1])) || line[1] == '-' || line[1] == '+' || line[1] == '.')) {
            if (error_line == 0) {
                error_line = line_number;
                error_reason = std::string("'") + line[0] + "' must be followed by a blank: " +
                               quoted(line.substr(0, line.find_first_of(" \t"))) + " is not a statement";
            }
            continue;
        }
        if (!is_vertex && !is_face) continue;  // vn, vt, g, o, usemtl, comments...
        if (const size_t hash = line.find('#'); hash != std::string_view::npos) {
            const size_t from = size_t(line.data() - text.data()) + hash;
            std::fill(text.begin() + std::ptrdiff_t(from), text.begin() + std::ptrdiff_t(line_end), ' ');
            line = line.substr(0, hash);
        }
        const std::string_view body = line.substr(1);

        if (error_line != 0) {  // after an error: only count vertices (see below)
            if (is_vertex) ++scan.vertex_count;
            continue;
        }

        if (is_vertex) {
            if (std::string bad = check_vertex(body); !bad.empty()) {
                error_line = line_number;
                error_reason = bad;
            }
            ++scan.vertex_count;
            continue;
        }

        size_t corners = 0;
        std::string bad = check_face(body, scan.vertex_count, corners, [&](long long index) {
            if (index > forward_max) {
                forward.push_back({line_number, index});
                forward_max = index;
            }
        });
        if (!bad.empty()) {
            // Keep scanning, counting vertices only: a forward index on an earlier
            // line can only be judged with the final count, and it comes first.
            error_line = line_number;
            error_reason = bad;
            continue;
        }
        scan.triangle_count += corners - 2;
    }

    const auto total = static_cast<long long>(scan.vertex_count);
    for (const ForwardIndex& f : forward) {
        if (f.index <= total) continue;
        if (error_line == 0 || f.line < error_line)
            return located_error(path, f.line,
                                 "face index " + std::to_string(f.index) + " out of range (file has " +
                                     std::to_string(total) + " vertices)");
        break;
    }
    if (error_line != 0) return located_error(path, error_line, error_reason);
    return scan;
}

/// The first line of tinyobjloader's message, for an error we did not foresee.
std::string first_line(const std::string& message) {
    const std::string line = message.substr(0, message.find('\n'));
    return line.empty() ? "tinyobjloader could not parse the file" : "tinyobjloader: " + line;
}

Expected<Mesh> parse_obj_unguarded(std::string bytes, const std::string& path) {
    // A UTF-8 byte-order mark (Windows tools write one) is not part of the first line.
    if (bytes.starts_with("\xEF\xBB\xBF")) bytes.erase(0, 3);

    auto scan = scan_obj(bytes, path);
    if (!scan) return Error{scan.error()};
    if (scan->triangle_count == 0) {
        if (bytes.find_first_not_of(" \t\r\n") == std::string::npos) return located_error(path, 0, "empty file (no triangles)");
        return located_error(path, 0, "no triangles (" + std::to_string(scan->vertex_count) + " vertices, no faces)");
    }

    // tinyobjloader reads the text we already hold (moved, not copied). No
    // material reader: mtllib/usemtl lines are ignored. triangulate=false: we fan-
    // triangulate below, because tinyobjloader's own triangulation splits quads
    // along the shorter diagonal and clips ears of larger polygons, which is not
    // the documented fan and can drop triangles of a degenerate polygon.
    std::istringstream stream(std::move(bytes));
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::string warn, err;
    if (!tinyobj::LoadObj(&attrib, &shapes, /*materials=*/nullptr, &warn, &err, &stream,
                          /*readMatFn=*/nullptr, /*triangulate=*/false, /*default_vcols_fallback=*/false))
        return located_error(path, 0, first_line(err));

    Mesh mesh;
    mesh.name = path;
    const size_t vertex_count = attrib.vertices.size() / 3;
    if (vertex_count > std::numeric_limits<uint32_t>::max())
        return located_error(path, 0, "too many vertices for 32-bit indices (" + std::to_string(vertex_count) + ")");
    if (vertex_count != scan->vertex_count)
        return located_error(path, 0, "tinyobjloader read " + std::to_string(vertex_count) + " vertices, expected " +
                                          std::to_string(scan->vertex_count));
    mesh.positions.resize(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i)
        mesh.positions[i] = {float(attrib.vertices[3 * i]), float(attrib.vertices[3 * i + 1]),
                             float(attrib.vertices[3 * i + 2])};

    // Fan triangulation: polygon (c0, c1, ..., c(k-1)) → (c0, ci, ci+1) for i = 1 .. k-2.
    mesh.indices.reserve(scan->triangle_count);
    for (const tinyobj::shape_t& shape : shapes) {
        const auto& corners = shape.mesh.indices;
        size_t first = 0;
        for (const unsigned int face_size : shape.mesh.num_face_vertices) {
            if (first + face_size > corners.size()) return located_error(path, 0, "tinyobjloader returned a truncated face list");
            auto corner = [&](size_t k) -> long long { return corners[first + k].vertex_index; };
            for (size_t k = 0; k < face_size; ++k)
                if (corner(k) < 0 || corner(k) >= static_cast<long long>(vertex_count))
                    return located_error(path, 0, "face index out of range after loading");
            for (size_t k = 1; k + 1 < face_size; ++k)
                mesh.indices.push_back({uint32_t(corner(0)), uint32_t(corner(k)), uint32_t(corner(k + 1))});
            first += face_size;
        }
    }
    if (mesh.indices.size() != scan->triangle_count)
        return located_error(path, 0, "tinyobjloader returned " + std::to_string(mesh.indices.size()) +
                                          " triangles, expected " + std::to_string(scan->triangle_count));
    return mesh;
}

}  // namespace

/// Runs `load` with nothing escaping to the caller: a huge file can still run out of memory.
template <class Load>
Expected<Mesh> guarded(const std::string& path, Load&& load) {
    try {
        return load();
    } catch (const std::exception& e) {
        return located_error(path, 0, std::string("cannot load: ") + e.what());
    } catch (...) {
        return located_error(path, 0, "cannot load: unknown error");
    }
}

Expected<Mesh> load_obj(const std::string& path) {
    return guarded(path, [&]() -> Expected<Mesh> {
        auto bytes = read_whole_file(path);
        if (!bytes) return Error{bytes.error()};
        return parse_obj_unguarded(std::move(*bytes), path);
    });
}

Expected<Mesh> parse_obj(std::string text, const std::string& name) {
    return guarded(name, [&]() -> Expected<Mesh> { return parse_obj_unguarded(std::move(text), name); });
}

}  // namespace accelviz

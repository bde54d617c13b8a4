#include "golden.h"

#include "app/gui/headless.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <thread>

namespace accelviz::testing {

namespace {

bool g_update = [] {
    const char* env = std::getenv("ACCELVIZ_UPDATE_GOLDEN");
    return env && *env && std::string(env) != "0";
}();

/// The golden dimmed to grey, mismatching pixels in red.
Image diff_image(const Image& golden, const Image& actual) {
    Image diff(golden.width, golden.height);
    for (int y = 0; y < golden.height; ++y)
        for (int x = 0; x < golden.width; ++x) {
            const Rgb g = golden.at(x, y), a = actual.at(x, y);
            const bool bad = std::abs(g.r - a.r) > kChannelTolerance || std::abs(g.g - a.g) > kChannelTolerance ||
                             std::abs(g.b - a.b) > kChannelTolerance;
            const uint8_t grey = uint8_t((g.r + g.g + g.b) / 6 + 40);
            diff.at(x, y) = bad ? Rgb{255, 0, 0} : Rgb{grey, grey, grey};
        }
    return diff;
}

}  // namespace

bool update_golden_mode() { return g_update; }
void set_update_golden_mode(bool on) { g_update = on; }

std::string screenshot_out_dir() {
    std::filesystem::create_directories(ACCELVIZ_SCREENSHOT_OUT);
    return ACCELVIZ_SCREENSHOT_OUT;
}

::testing::AssertionResult matches_golden(const Image& actual, const std::string& name) {
    const std::string golden_path = std::string(ACCELVIZ_GOLDEN_DIR) + "/" + name + ".png";
    const std::string actual_path = screenshot_out_dir() + "/" + name + ".png";
    if (auto err = write_png(actual, actual_path)) return ::testing::AssertionFailure() << err->message;
    if (update_golden_mode()) {
        if (auto err = write_png(actual, golden_path)) return ::testing::AssertionFailure() << err->message;
        return ::testing::AssertionSuccess() << "updated " << golden_path;
    }

    auto golden = read_png(golden_path);
    if (!golden)
        return ::testing::AssertionFailure()
               << "no golden image: " << golden.error() << "\n  rendered: " << actual_path
               << "\n  (run with ACCELVIZ_UPDATE_GOLDEN=1 to create it)";
    if (golden->width != actual.width || golden->height != actual.height)
        return ::testing::AssertionFailure() << name << ": size " << actual.width << "x" << actual.height
                                             << " differs from the golden's " << golden->width << "x"
                                             << golden->height << "\n  rendered: " << actual_path;
    size_t mismatched = 0;
    int worst = 0;
    for (size_t i = 0; i < actual.pixels.size(); ++i) {
        const Rgb g = golden->pixels[i], a = actual.pixels[i];
        const int d = std::max({std::abs(g.r - a.r), std::abs(g.g - a.g), std::abs(g.b - a.b)});
        worst = std::max(worst, d);
        if (d > kChannelTolerance) ++mismatched;
    }
    const double fraction = double(mismatched) / double(actual.pixels.size());
    if (fraction <= kMaxMismatchFraction)
        return ::testing::AssertionSuccess() << mismatched << " pixels differ by more than " << kChannelTolerance;

    const std::string diff_path = screenshot_out_dir() + "/" + name + ".diff.png";
    (void)write_png(diff_image(*golden, actual), diff_path);
    return ::testing::AssertionFailure() << name << ": " << mismatched << " of " << actual.pixels.size()
                                         << " pixels (" << 100.0 * fraction << "%, allowed "
                                         << 100.0 * kMaxMismatchFraction << "%) differ by more than "
                                         << kChannelTolerance << " (worst " << worst << ")\n  rendered: "
                                         << actual_path << "\n  diff:     " << diff_path
                                         << "\n  golden:   " << golden_path;
}

::testing::AssertionResult view_matches_golden(const AppState& state, WindowView view, int width, int height,
                                               const std::string& name) {
    auto image = render_gui_view_headless(state, view, width, height);
    if (!image) return ::testing::AssertionFailure() << "rendering " << to_string(view) << " for " << name << ": " << image.error();
    return matches_golden(*image, name);
}

MeasureClock ticking_clock() {
    auto now = std::make_shared<double>(0.0);
    return [now] { return *now += 1e-3; };
}

void draw_until_loaded(HeadlessApp& app, AppState& state, int seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    while ((app.session().loader.busy() || app.session().loader.has_result()) &&
           std::chrono::steady_clock::now() < deadline) {
        app.draw(state, {});
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    app.draw(state, {});
}

void use_ticking_clock(Session& session) {
    session.comparison.options.clock = ticking_clock();
    session.comparison.options.naive_test_budget = 1;
}

}  // namespace accelviz::testing

// The shipped presets (assets/presets): each one loads and renders headless, they
// sort in lecture order, PageDown / PageUp step through a list, and one preset
// has a golden image.
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "app/gui/headless.h"
#include "app/gui/presets.h"
#include "app/gui/session.h"
#include "golden.h"

namespace accelviz {
namespace {

namespace fs = std::filesystem;

const std::string kPresetDir = std::string(ACCELVIZ_SOURCE_DIR) + "/assets/presets";

/// A directory of preset files (name, JSON text) under the test output.
fs::path write_presets(const std::string& dir_name, const std::vector<std::pair<std::string, std::string>>& files) {
    const fs::path dir = fs::path(ACCELVIZ_SCREENSHOT_OUT) / dir_name;
    fs::create_directories(dir);
    for (const auto& [name, text] : files) std::ofstream(dir / name) << text;
    return dir;
}

/// Until the worker has finished what it was asked for.
void wait_for_loader(const Session& session) {
    while (session.loader.busy()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

TEST(Presets, ShippedOnesAreFoundAndSortInLectureOrder) {
    EXPECT_EQ(fs::path(find_presets_dir()), fs::path(kPresetDir).lexically_normal());
    const std::vector<PresetInfo> presets = list_presets(kPresetDir);
    ASSERT_GE(presets.size(), 10u);
    for (size_t i = 0; i < presets.size(); ++i) {
        // "NN-name": two digits, numbered from 01 without gaps, so that file order is lecture order.
        char number[32];
        std::snprintf(number, sizeof number, "%02zu-", i + 1);
        EXPECT_EQ(presets[i].name.rfind(number, 0), 0u) << presets[i].name;
        EXPECT_NE(presets[i].title, presets[i].name) << presets[i].path << " has no \"title\"";
    }
}

TEST(Presets, EveryShippedPresetLoadsAndRendersHeadless) {
    for (const PresetInfo& preset : list_presets(kPresetDir)) {
        SCOPED_TRACE(preset.path);
        auto state = load_app_state_file(preset.path);
        ASSERT_TRUE(state) << state.error();
        auto image = render_gui_view_headless(*state, WindowView::Gui, 320, 200);
        ASSERT_TRUE(image) << image.error();
        // The 3D view (right of the sidebar) shows something besides the background.
        std::set<uint32_t> colours;
        for (int y = 0; y < image->height; y += 2)
            for (int x = image->width / 2; x < image->width; x += 2) {
                const Rgb c = image->at(x, y);
                colours.insert(uint32_t(c.r) << 16 | uint32_t(c.g) << 8 | c.b);
            }
        EXPECT_GT(colours.size(), 20u);
    }
}

TEST(Presets, PageDownAndPageUpStepThroughTheListAndStopAtItsEnds) {
    const fs::path dir = write_presets("preset_list", {
        {"02-second.json", R"({"title": "Second", "scene": "builtin:cube", "structure": {"type": "grid"}})"},
        {"01-first.json", R"({"title": "First", "scene": "builtin:cube", "structure": {"type": "bvh"}})"},
        {"notes.txt", "not a preset"}});
    Session session;
    PresetList& list = session.presets;
    list.set_dir(dir.string());
    ASSERT_EQ(list.entries().size(), 2u);
    EXPECT_EQ(list.entries()[0].title, "First");
    AppState state;
    list.step(+1, state, session);
    EXPECT_EQ(list.current(), 0);
    EXPECT_EQ(state.accel.type, AccelType::Bvh);
    list.step(+1, state, session);
    EXPECT_EQ(list.current(), 1);
    EXPECT_EQ(state.accel.type, AccelType::Grid);
    EXPECT_EQ(list.caption(), "Preset 2/2: Second");
    list.step(+1, state, session);  // the last one stays
    EXPECT_EQ(list.current(), 1);
    list.step(-1, state, session);
    EXPECT_EQ(list.current(), 0);
    EXPECT_EQ(state.accel.type, AccelType::Bvh);
    wait_for_loader(session);
}

TEST(Presets, TheCaptionStaysUntilThePresetsSceneIsOnScreen) {
    // A scene that takes longer to load than the caption's few seconds: the caption
    // must still be up when it arrives (it counts from then, not from the key press).
    const fs::path dir = write_presets("preset_caption", {
        {"01-slow.json", R"({"title": "Slow", "scene": "builtin:soup?n=200000", "structure": {"type": "bvh"}})"}});
    Session session;
    session.presets.set_dir(dir.string());
    AppState state;
    session.presets.step(+1, state, session);
    ASSERT_TRUE(session.loader.busy());
    std::this_thread::sleep_for(std::chrono::milliseconds(4500));  // longer than the caption lasts
    wait_for_loader(session);
    EXPECT_TRUE(session.presets.caption_fresh()) << "the caption went before the scene came";
    session.take_finished_load(state);
    ASSERT_TRUE(session.scene);
    EXPECT_TRUE(session.presets.caption_fresh()) << "the caption went as the scene came";
}

TEST(Presets, TheWindowOpenedOnAPresetGoesOnFromIt) {
    const fs::path dir = write_presets("preset_opened_with", {
        {"01-first.json", R"({"title": "First", "scene": "builtin:cube", "structure": {"type": "bvh"}})"},
        {"02-second.json", R"({"title": "Second", "scene": "builtin:cube", "structure": {"type": "grid"}})"},
        {"elsewhere.json.txt", "{}"}});
    Session session;
    PresetList& list = session.presets;
    list.set_dir(dir.string());
    list.opened_with((dir / "elsewhere.json.txt").string(), session);  // not one of the list
    EXPECT_EQ(list.current(), -1);
    // Spelled another way than the list spells it: the same file.
    list.opened_with((dir / ".." / dir.filename() / "02-second.json").string(), session);
    EXPECT_EQ(list.current(), 1);
    EXPECT_EQ(list.caption(), "Preset 2/2: Second");
    EXPECT_TRUE(list.caption_fresh());
    AppState state;
    list.step(-1, state, session);  // PageUp goes on from it
    EXPECT_EQ(list.current(), 0);
    EXPECT_EQ(state.accel.type, AccelType::Bvh);
    wait_for_loader(session);
}

TEST(Presets, APresetOfTheSceneOnScreenOverridesALoadStillComing) {
    // Two quick PageDowns: the first preset's scene is still loading when the second,
    // whose scene and structure are the ones on screen, is chosen. The second wins:
    // the first one's scene must not arrive under the second one's caption.
    const fs::path dir = write_presets("preset_overrides", {
        {"01-big.json", R"({"title": "Big", "scene": "builtin:soup?n=300000", "structure": {"type": "kd"}})"},
        {"02-cube.json", R"({"title": "Cube", "scene": "builtin:cube", "structure": {"type": "bvh"}})"}});
    Session session;
    AppState state;
    state.scene = "builtin:cube";
    session.open_scene(state, state.scene);
    wait_for_loader(session);
    session.take_finished_load(state);
    ASSERT_TRUE(session.scene);
    ASSERT_EQ(session.scene->accel_config.type, AccelType::Bvh);
    session.presets.set_dir(dir.string());
    session.presets.step(+1, state, session);  // 01: a 300k-triangle KD build, seconds
    ASSERT_TRUE(session.loader.busy());
    session.presets.step(+1, state, session);  // 02: what is on screen
    wait_for_loader(session);
    session.take_finished_load(state);
    EXPECT_EQ(session.presets.current(), 1);
    EXPECT_EQ(session.scene->source, "builtin:cube");
    EXPECT_EQ(session.scene->accel_config.type, AccelType::Bvh);
    EXPECT_EQ(state.scene, "builtin:cube");
    EXPECT_EQ(state.accel.type, AccelType::Bvh);
}

TEST(Presets, ABadPresetFileIsAMessageAndChangesNothing) {
    const fs::path dir = write_presets("preset_list_bad", {
        {"01-broken.json", R"({"structure": {"type": "bvh", "bvh": {"builder": "best"}}})"}});
    Session session;
    session.presets.set_dir(dir.string());
    AppState state;
    state.accel.type = AccelType::Kd;
    session.presets.step(+1, state, session);
    EXPECT_EQ(session.presets.current(), -1);
    EXPECT_EQ(state.accel.type, AccelType::Kd);
    EXPECT_NE(session.message.find("01-broken.json: structure.bvh.builder"), std::string::npos) << session.message;
}

TEST(GoldenImage, PresetBvhSahGuiFrame) {
    auto state = load_app_state_file(kPresetDir + "/04-bvh-sah.json");
    ASSERT_TRUE(state) << state.error();
    auto image = render_gui_view_headless(*state, WindowView::Gui, 800, 450);
    ASSERT_TRUE(image) << image.error();
    EXPECT_TRUE(testing::matches_golden(*image, "preset_04_bvh_sah_gui"));
}

}  // namespace
}  // namespace accelviz

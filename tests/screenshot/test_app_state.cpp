// AppState <-> JSON and the camera controls: plain functions, no GL.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "app/gui/app_state.h"
#include "app/gui/camera_control.h"

namespace accelviz {
namespace {

double distance(Vec3d a, Vec3d b) { return std::sqrt(dot(a - b, a - b)); }

TEST(AppStateJson, RoundTripKeepsEveryField) {
    AppState s;
    s.scene = "builtin:teapot?n=4";
    s.accel.type = AccelType::Naive;
    s.camera = CameraParams{{1, 2, 3}, {0, 0.5, 0}, {0, 1, 0}, 35};
    s.view.ui_scale = 2.0f;
    s.view.light_theme = true;
    s.view.background = {10, 20, 30};
    s.view.show_ui = false;
    s.view.show_bounds = false;
    s.light.shadows = true;
    s.light.reflections = true;
    s.light.position = Vec3d{1.5, -2.25, 1e-7};
    s.view.heat_rays = HeatRays::Reflection;
    s.stepper.any_hit = true;
    s.scaling.open = true;
    s.scaling.max_triangles = 2.5e6;
    s.scaling.structures = {AccelType::Kd, AccelType::Bvh};
    auto back = app_state_from_json(to_json(s));
    ASSERT_TRUE(back) << back.error();
    EXPECT_EQ(to_json(*back), to_json(s));
    EXPECT_TRUE(back->light == s.light);
    EXPECT_EQ(back->view.heat_rays, HeatRays::Reflection);
    EXPECT_TRUE(back->stepper.any_hit);
    EXPECT_TRUE(back->scaling == s.scaling);
}

TEST(AppStateJson, TheScalingChartsSettingsAreChecked) {
    const auto error_of = [](const char* text) {
        auto s = app_state_from_json(nlohmann::json::parse(text));
        return s ? std::string() : s.error();
    };
    EXPECT_NE(error_of(R"({"scaling": {"max_triangles": 5}})").find("scaling.max_triangles"), std::string::npos);
    EXPECT_NE(error_of(R"({"scaling": {"structures": ["naive"]}})").find("scaling.structures"), std::string::npos);
    EXPECT_NE(error_of(R"({"scaling": {"structures": ["bhv"]}})").find("scaling.structures"), std::string::npos);
    EXPECT_NE(error_of(R"({"scaling": {"structures": []}})").find("scaling.structures"), std::string::npos);
    auto twice = app_state_from_json(nlohmann::json::parse(R"({"scaling": {"structures": ["grid", "grid", "bvh"]}})"));
    ASSERT_TRUE(twice) << twice.error();
    EXPECT_EQ(twice->scaling.structures, (std::vector<AccelType>{AccelType::Grid, AccelType::Bvh}));
}

TEST(AppStateJson, ALightPositionMustBeFinite) {
    for (const char* text : {R"({"light": {"position": [0, 1e13, 0]}})", R"({"light": {"position": [0, 1]}})",
                             R"({"light": {"shadows": 1}})"}) {
        auto bad = app_state_from_json(nlohmann::json::parse(text));
        ASSERT_FALSE(bad) << text;
        EXPECT_NE(bad.error().find("light"), std::string::npos) << bad.error();
    }
    auto none = app_state_from_json(nlohmann::json::parse(R"({"light": {"position": null}})"));
    ASSERT_TRUE(none) << none.error();
    EXPECT_FALSE(none->light.point_light()) << "no position, no shadows, no reflections: the headlight";
}

TEST(AppStateJson, StepperRayAndStepRoundTripExactly) {
    AppState s;
    s.stepper.open = true;
    Ray ray;
    ray.origin = {0.1f, -2.5f, 3.0f};
    ray.dir = {0.267261237f, 0.534522474f, -0.801783681f};
    s.stepper.ray = ray;
    s.stepper.step = 17;
    s.stepper.pixel = std::array<int, 2>{640, 360};
    auto back = app_state_from_json(nlohmann::json::parse(to_json(s).dump()));
    ASSERT_TRUE(back) << back.error();
    EXPECT_TRUE(back->stepper == s.stepper);
    EXPECT_EQ(back->stepper.ray->dir, ray.dir);  // bit for bit: the same ray, the same events
    EXPECT_EQ(back->stepper.ray->t_max, kInfinity);
    auto bad = app_state_from_json(nlohmann::json::parse(R"({"stepper": {"ray": {"origin": [0,0,0], "dir": [0,0,0]}}})"));
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().find("stepper.ray.dir"), std::string::npos) << bad.error();
}

TEST(AppStateJson, MissingFieldsKeepDefaultsAndNullCameraMeansSceneDefault) {
    auto s = app_state_from_json(nlohmann::json::parse(R"({"scene": "builtin:cube", "camera": null})"));
    ASSERT_TRUE(s) << s.error();
    EXPECT_EQ(s->scene, "builtin:cube");
    EXPECT_FALSE(s->camera.has_value());
    EXPECT_EQ(s->view.ui_scale, 1.0f);
}

TEST(AppStateJson, BadValuesAreOneLineErrorsNamingTheField) {
    auto bad_eye = app_state_from_json(nlohmann::json::parse(R"({"camera": {"eye": [1, 2]}})"));
    ASSERT_FALSE(bad_eye);
    EXPECT_NE(bad_eye.error().find("camera.eye"), std::string::npos) << bad_eye.error();
    auto same = app_state_from_json(nlohmann::json::parse(R"({"camera": {"eye": [0,0,0], "target": [0,0,0]}})"));
    ASSERT_FALSE(same);
    auto scale = app_state_from_json(nlohmann::json::parse(R"({"view": {"ui_scale": 9}})"));
    ASSERT_FALSE(scale);
    EXPECT_NE(scale.error().find("ui_scale"), std::string::npos);
}

TEST(AppStateJson, WrongKindsOfValueNameTheField) {
    // field -> the JSON that holds a value of the wrong kind there
    const std::pair<const char*, const char*> cases[] = {
        {"structure.bvh.bins: expected a whole number, got \"x\"", R"({"structure": {"bvh": {"bins": "x"}}})"},
        {"structure.bvh.bins: expected a whole number, got 16.9", R"({"structure": {"bvh": {"bins": 16.9}}})"},
        {"structure.bvh.bins: expected a whole number, got true", R"({"structure": {"bvh": {"bins": true}}})"},
        {"structure.bvh.bins: expected a whole number, got 4294967300", R"({"structure": {"bvh": {"bins": 4294967300}}})"},
        {"structure.leaf_size: expected a whole number", R"({"structure": {"leaf_size": "x"}})"},
        {"structure.kd.cost_trav: expected a number, got true", R"({"structure": {"kd": {"cost_trav": true}}})"},
        {"structure.grid.mailbox: expected true or false, got 1", R"({"structure": {"grid": {"mailbox": 1}}})"},
        {"build_step.bins: expected a whole number", R"({"build_step": {"bins": 2.5}})"},
        {"camera.eye: expected [x, y, z] (three numbers)", R"({"camera": {"eye": ["a", 0, 0]}})"},
        {"view.ui_scale: expected a number, got \"big\"", R"({"view": {"ui_scale": "big"}})"},
        // Found by fuzz_app_state: a float beyond int's range was converted (undefined behaviour).
        {"stepper.pixel: expected a whole number from 0 to 16383, got 4.3", R"({"stepper": {"pixel": [3, 4.3e82]}})"},
        {"stepper.pixel: expected a whole number from 0 to 16383, got -1", R"({"stepper": {"pixel": [-1, 0]}})"},
        {"view.background: expected a whole number from 0 to 255, got 1e+300", R"({"view": {"background": [1e300, 0, 0]}})"},
        {"view.background: expected a whole number from 0 to 255, got 256", R"({"view": {"background": [256, 0, 0]}})"},
    };
    for (const auto& [expected, json] : cases) {
        auto state = app_state_from_json(nlohmann::json::parse(json));
        ASSERT_FALSE(state) << json;
        EXPECT_NE(state.error().find(expected), std::string::npos) << state.error();
    }
}

TEST(AppStateFile, ACheckedLoadRefusesAStructureTheBuildWouldRefuse) {
    // Reading keeps a bad structure value (command-line flags may still replace it);
    // the window's checked load refuses it, naming the file.
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(ACCELVIZ_SCREENSHOT_OUT) / "preset_checked";
    fs::create_directories(dir);
    std::ofstream(dir / "bins1.json") << R"({"structure": {"type": "bvh", "bvh": {"bins": 1}}})";
    std::ofstream(dir / "kd_unused.json") << R"({"structure": {"type": "kd", "bvh": {"bins": 1}}})";
    const std::string bins1 = (dir / "bins1.json").string();
    EXPECT_TRUE(load_app_state_file(bins1));
    auto checked = load_app_state_file_checked(bins1);
    ASSERT_FALSE(checked);
    EXPECT_NE(checked.error().find("bins1.json: structure: --bins must be between 2 and 64 (got 1)"), std::string::npos)
        << checked.error();
    // Only the structure the state selects is checked, as only it is built.
    EXPECT_TRUE(load_app_state_file_checked((dir / "kd_unused.json").string()));
}

TEST(AppStateFile, RelativeObjPathIsTakenFromThePresetsDirectoryWhenTheFileIsThere) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(ACCELVIZ_SCREENSHOT_OUT) / "preset_paths";
    fs::create_directories(dir / "meshes");
    std::ofstream(dir / "meshes" / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::ofstream(dir / "beside.json") << R"({"scene": "meshes/tri.obj"})";
    std::ofstream(dir / "elsewhere.json") << R"({"scene": "no/such/mesh.obj"})";
    std::ofstream(dir / "builtin.json") << R"({"scene": "builtin:cube"})";

    auto beside = load_app_state_file((dir / "beside.json").string());
    ASSERT_TRUE(beside) << beside.error();
    EXPECT_EQ(fs::path(beside->scene), (dir / "meshes" / "tri.obj").lexically_normal());
    auto elsewhere = load_app_state_file((dir / "elsewhere.json").string());
    ASSERT_TRUE(elsewhere) << elsewhere.error();
    EXPECT_EQ(elsewhere->scene, "no/such/mesh.obj");  // kept: relative to the working directory
    auto builtin = load_app_state_file((dir / "builtin.json").string());
    ASSERT_TRUE(builtin) << builtin.error();
    EXPECT_EQ(builtin->scene, "builtin:cube");
}

TEST(AppStateFile, ErrorsNameTheFileAndTheProblem) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(ACCELVIZ_SCREENSHOT_OUT) / "preset_errors";
    fs::create_directories(dir);
    std::ofstream(dir / "truncated.json") << "{\"scene\": \n";
    auto missing = load_app_state_file((dir / "missing.json").string());
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().find("missing.json: cannot read"), std::string::npos) << missing.error();
    auto truncated = load_app_state_file((dir / "truncated.json").string());
    ASSERT_FALSE(truncated);
    EXPECT_NE(truncated.error().find("truncated.json: not valid JSON"), std::string::npos) << truncated.error();
    EXPECT_NE(truncated.error().find("line 2"), std::string::npos) << truncated.error();
    EXPECT_EQ(truncated.error().find('\n'), std::string::npos);
    // A number too big for a double: nlohmann throws out_of_range, not parse_error.
    std::ofstream(dir / "huge.json") << "{\"scene\": \"builtin:cube\", \"view\": {\"ui_scale\": 1e999}}";
    auto huge = load_app_state_file((dir / "huge.json").string());
    ASSERT_FALSE(huge);
    EXPECT_NE(huge.error().find("huge.json: not valid JSON: number overflow"), std::string::npos) << huge.error();
}

TEST(CameraControl, OrbitKeepsDistanceToTargetAndStaysOffThePole) {
    CameraParams c{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45};
    orbit(c, 0.7, 0.3);
    EXPECT_NEAR(distance(c.eye, c.target), 5.0, 1e-9);
    orbit(c, 0.0, 10.0);  // far past straight above: clamped
    EXPECT_NEAR(distance(c.eye, c.target), 5.0, 1e-9);
    EXPECT_FALSE(validate(c).has_value()) << "the camera stays valid";
    EXPECT_LT(c.eye.y / 5.0, 1.0);
}

TEST(CameraControl, PanMovesEyeAndTargetTogether) {
    CameraParams c{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45};
    pan(c, 0.1, 0.0);
    EXPECT_NEAR(c.eye.z - c.target.z, 5.0, 1e-12);
    EXPECT_LT(c.target.x, 0.0) << "the scene moves right: the camera moves left";
}

TEST(CameraControl, FrameBoundsCentresAndFitsTheScene) {
    CameraParams c{{10, 0, 0}, {3, 3, 3}, {0, 1, 0}, 45};
    Aabb box;
    box.grow({-1, -1, -1});
    box.grow({1, 1, 1});
    frame_bounds(c, box, 16.0 / 9.0);
    EXPECT_NEAR(distance(c.target, {0, 0, 0}), 0.0, 1e-12);
    // The enclosing sphere (radius sqrt 3) fits the vertical half-angle of 22.5 degrees.
    const double d = distance(c.eye, c.target);
    EXPECT_GE(std::sqrt(3.0) / d, 0.0);
    EXPECT_LE(std::sqrt(3.0) / d, std::sin(22.5 * 3.14159265358979 / 180.0) + 1e-9);
}

TEST(CameraControl, CliFlagsReproduceTheCamera) {
    CameraParams c{{1.5, 2, -3.25}, {0, 0.5, 0}, {0, 1, 0}, 40};
    EXPECT_EQ(camera_cli_flags(c), "--eye 1.5,2,-3.25 --target 0,0.5,0 --up 0,1,0 --fov 40");
}

}  // namespace
}  // namespace accelviz

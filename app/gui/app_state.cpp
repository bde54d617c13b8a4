#include "app/gui/app_state.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace accelviz {

int font_pixels(float ui_scale) { return std::clamp(int(std::lround(16.0f * ui_scale)), 8, 64); }

namespace {

nlohmann::json vec3_json(Vec3d v) { return {v.x, v.y, v.z}; }
nlohmann::json rgb_json(Rgb c) { return {c.r, c.g, c.b}; }

Vec3d read_vec3(const nlohmann::json& j, const char* field) {
    if (!j.is_array() || j.size() != 3) throw std::runtime_error(std::string(field) + ": expected [x, y, z]");
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

Rgb read_rgb(const nlohmann::json& j, const char* field) {
    if (!j.is_array() || j.size() != 3) throw std::runtime_error(std::string(field) + ": expected [r, g, b]");
    auto channel = [&](int i) {
        const int v = j[size_t(i)].get<int>();
        if (v < 0 || v > 255) throw std::runtime_error(std::string(field) + ": channels are 0..255");
        return uint8_t(v);
    };
    return {channel(0), channel(1), channel(2)};
}

}  // namespace

nlohmann::json to_json(const AppState& s) {
    nlohmann::json j;
    j["scene"] = s.scene;
    j["structure"] = {{"type", s.accel.type}};
    if (s.camera)
        j["camera"] = {{"eye", vec3_json(s.camera->eye)},
                       {"target", vec3_json(s.camera->target)},
                       {"up", vec3_json(s.camera->up)},
                       {"fov", s.camera->fov_deg}};
    else
        j["camera"] = nullptr;
    j["view"] = {{"ui_scale", s.view.ui_scale},   {"light_theme", s.view.light_theme},
                 {"background", rgb_json(s.view.background)}, {"show_ui", s.view.show_ui},
                 {"show_help", s.view.show_help}, {"show_bounds", s.view.show_bounds}};
    return j;
}

Expected<AppState> app_state_from_json(const nlohmann::json& j) {
    AppState s;
    try {
        if (!j.is_object()) return Error{"state: expected a JSON object"};
        s.scene = j.value("scene", s.scene);
        if (j.contains("structure")) s.accel.type = j["structure"].value("type", s.accel.type);
        if (j.contains("camera") && !j["camera"].is_null()) {
            const auto& c = j["camera"];
            CameraParams p;
            if (c.contains("eye")) p.eye = read_vec3(c["eye"], "camera.eye");
            if (c.contains("target")) p.target = read_vec3(c["target"], "camera.target");
            if (c.contains("up")) p.up = read_vec3(c["up"], "camera.up");
            p.fov_deg = c.value("fov", p.fov_deg);
            if (auto err = validate(p)) return *err;
            s.camera = p;
        }
        if (j.contains("view")) {
            const auto& v = j["view"];
            s.view.ui_scale = v.value("ui_scale", s.view.ui_scale);
            if (!(s.view.ui_scale >= 0.5f && s.view.ui_scale <= 4.0f))
                return Error{"view.ui_scale: must be between 0.5 and 4"};
            s.view.light_theme = v.value("light_theme", s.view.light_theme);
            if (v.contains("background")) s.view.background = read_rgb(v["background"], "view.background");
            s.view.show_ui = v.value("show_ui", s.view.show_ui);
            s.view.show_help = v.value("show_help", s.view.show_help);
            s.view.show_bounds = v.value("show_bounds", s.view.show_bounds);
        }
    } catch (const std::exception& e) {  // nlohmann type errors and ours
        return Error{std::string("state: ") + e.what()};
    }
    return s;
}

}  // namespace accelviz

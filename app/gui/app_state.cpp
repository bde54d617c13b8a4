#include "app/gui/app_state.h"

#include <algorithm>
#include <iterator>
#include <limits>
#include <optional>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <sstream>
#include <string>
#include <type_traits>

#include "core/traversal/event_json.h"

namespace accelviz {

int font_pixels(float ui_scale) { return std::clamp(int(std::lround(16.0f * ui_scale)), 8, 64); }

namespace {

nlohmann::json vec3_json(Vec3d v) { return {v.x, v.y, v.z}; }
nlohmann::json rgb_json(Rgb c) { return {c.r, c.g, c.b}; }

/// obj[key] as a T when present (else `current`), or an error naming the field:
/// `view.ui_scale: expected a number, got "big"` (nlohmann's own message names no field).
/// Integer fields take only whole numbers that fit (no 16.9, true or 1e10), number
/// fields only numbers (no true).
template <class T>
T read(const nlohmann::json& obj, const char* key, const T& current, const char* section) {
    const auto it = obj.find(key);
    if (it == obj.end()) return current;
    constexpr bool kFlag = std::is_same_v<T, bool>;
    constexpr bool kWhole = std::is_integral_v<T> && !kFlag;
    bool ok = false;
    if constexpr (kFlag) {
        ok = it->is_boolean();
    } else if constexpr (kWhole) {  // JSON keeps non-negative integers as unsigned, negative ones as signed
        using Limits = std::numeric_limits<T>;
        if (it->is_number_unsigned()) ok = it->template get<uint64_t>() <= uint64_t(Limits::max());
        else if (it->is_number_integer())
            ok = it->template get<int64_t>() >= int64_t(Limits::min()) && it->template get<int64_t>() <= int64_t(Limits::max());
    } else if constexpr (std::is_arithmetic_v<T>) {
        ok = it->is_number();
    } else {
        ok = it->is_string();
    }
    if (!ok) {
        const char* expected = kFlag                     ? "true or false"
                               : kWhole                  ? "a whole number"
                               : std::is_arithmetic_v<T> ? "a number"
                                                         : "a string";
        const std::string field = *section ? std::string(section) + "." + key : std::string(key);
        throw std::runtime_error(field + ": expected " + expected + ", got " + it->dump());
    }
    return it->template get<T>();
}

/// An optional field: absent keeps `current`, null unsets it, otherwise read() as a T.
template <class T>
std::optional<T> read(const nlohmann::json& obj, const char* key, const std::optional<T>& current, const char* section) {
    const auto it = obj.find(key);
    if (it == obj.end()) return current;
    if (it->is_null()) return std::nullopt;
    return read(obj, key, T{}, section);
}

/// nlohmann's message without its "[json.exception.type_error.302] " tag.
std::string without_json_tag(const std::string& what) {
    if (what.rfind("[json.exception.", 0) != 0) return what;
    const size_t tag = what.find("] ");
    return tag == std::string::npos ? what : what.substr(tag + 2);
}

Vec3d read_vec3(const nlohmann::json& j, const char* field) {
    const bool numbers = j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number();
    if (!numbers) throw std::runtime_error(std::string(field) + ": expected [x, y, z] (three numbers), got " + j.dump());
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

/// A whole number in [lo, hi] (no 16.9, true or 1e82: a float out of int's range
/// would be undefined behaviour to convert), or fail naming the field.
int read_whole(const nlohmann::json& j, const std::string& field, int lo, int hi) {
    bool ok = false;
    if (j.is_number_unsigned()) ok = j.get<uint64_t>() <= uint64_t(hi);
    else if (j.is_number_integer()) ok = j.get<int64_t>() >= lo && j.get<int64_t>() <= hi;
    if (!ok)
        throw std::runtime_error(field + ": expected a whole number from " + std::to_string(lo) + " to " +
                                 std::to_string(hi) + ", got " + j.dump());
    return int(j.get<int64_t>());
}

Rgb read_rgb(const nlohmann::json& j, const char* field) {
    if (!j.is_array() || j.size() != 3) throw std::runtime_error(std::string(field) + ": expected [r, g, b]");
    auto channel = [&](int i) { return uint8_t(read_whole(j[size_t(i)], std::string(field), 0, 255)); };
    return {channel(0), channel(1), channel(2)};
}

/// A named enum value: `parse` it or fail naming the field.
template <class Parse>
auto read_enum(const nlohmann::json& j, const char* field, Parse parse) {
    const std::string name = j.get<std::string>();
    auto value = parse(name);
    if (!value) throw std::runtime_error(std::string(field) + ": unknown value '" + name + "'");
    return *value;
}

/// A value of an enum with a table of names, or fail naming the field and the names it takes.
template <class Enum, size_t N>
Enum read_named(const nlohmann::json& j, const char* field, const EnumNames<Enum, N>& names) {
    if (j.is_string())
        if (auto value = names.parse(j.get<std::string>())) return *value;
    std::ostringstream message;
    message << field << ": must be " << names.listed() << " (got " << j.dump() << ")";
    throw std::runtime_error(message.str());
}

/// A float written by float_to_json: a number, or "inf", "-inf", "nan".
float read_float(const nlohmann::json& j, const char* field) {
    if (j.is_number()) return j.get<float>();
    if (j.is_string()) {
        const std::string text = j.get<std::string>();
        if (text == "inf") return kInfinity;
        if (text == "-inf") return -kInfinity;
    }
    throw std::runtime_error(std::string(field) + ": expected a number, \"inf\" or \"-inf\"");
}

}  // namespace

nlohmann::json accel_config_json(const AccelConfig& a) {
    nlohmann::json j;
    j["type"] = std::string(to_string(a.type));
    j["bvh"] = {{"builder", std::string(to_string(a.bvh.builder))},
                {"bins", a.bvh.bins},
                {"max_leaf_size", a.bvh.max_leaf_size},
                {"cost_trav", a.bvh.cost_trav},
                {"cost_isect", a.bvh.cost_isect},
                {"width", a.bvh.width},
                {"traversal", std::string(to_string(a.bvh_traversal))}};
    j["grid"] = {{"density", a.grid.density},
                 {"insert", std::string(to_string(a.grid.insert))},
                 {"mailbox", a.grid.mailbox}};
    j["kd"] = {{"builder", std::string(to_string(a.kd.builder))},
               {"max_depth", a.kd.max_depth},
               {"leaf_size", a.kd.leaf_size},
               {"cost_trav", a.kd.cost_trav},
               {"cost_isect", a.kd.cost_isect},
               {"empty_bonus", a.kd.empty_bonus},
               {"clip", std::string(to_string(a.kd.clip))},
               {"strict_cell", a.kd.strict_cell},
               {"mailbox", a.kd.mailbox}};
    j["octree"] = {{"max_depth", a.octree.max_depth},
                   {"leaf_size", a.octree.leaf_size},
                   {"clip", std::string(to_string(a.octree.clip))},
                   {"mailbox", a.octree.mailbox}};
    j["bsp"] = {{"max_depth", a.bsp.max_depth},
                {"leaf_size", a.bsp.leaf_size},
                {"candidates", a.bsp.candidates},
                {"mailbox", a.bsp.mailbox}};
    j["triangle_test"] = std::string(to_string(a.triangle_test));
    // The CLI's shared overrides, only when set.
    if (a.leaf_size) j["leaf_size"] = *a.leaf_size;
    if (a.cost_trav) j["cost_trav"] = *a.cost_trav;
    if (a.cost_isect) j["cost_isect"] = *a.cost_isect;
    if (!a.structure_file.empty()) j["file"] = a.structure_file;  // a structure from a file, not built
    return j;
}

namespace {

void read_accel(const nlohmann::json& j, AccelConfig& a) {
    if (j.contains("type")) a.type = read_enum(j["type"], "structure.type", parse_accel_type);
    if (j.contains("bvh")) {
        const auto& b = j["bvh"];
        if (b.contains("builder")) a.bvh.builder = read_enum(b["builder"], "structure.bvh.builder", parse_bvh_builder);
        a.bvh.bins = read(b, "bins", a.bvh.bins, "structure.bvh");
        a.bvh.max_leaf_size = read(b, "max_leaf_size", a.bvh.max_leaf_size, "structure.bvh");
        a.bvh.cost_trav = read(b, "cost_trav", a.bvh.cost_trav, "structure.bvh");
        a.bvh.cost_isect = read(b, "cost_isect", a.bvh.cost_isect, "structure.bvh");
        a.bvh.width = read(b, "width", a.bvh.width, "structure.bvh");
        if (b.contains("traversal"))
            a.bvh_traversal = read_enum(b["traversal"], "structure.bvh.traversal", parse_bvh_traversal);
    }
    if (j.contains("grid")) {
        const auto& g = j["grid"];
        a.grid.density = read(g, "density", a.grid.density, "structure.grid");
        if (g.contains("insert")) a.grid.insert = read_enum(g["insert"], "structure.grid.insert", parse_grid_insert);
        a.grid.mailbox = read(g, "mailbox", a.grid.mailbox, "structure.grid");
    }
    if (j.contains("kd")) {
        const auto& k = j["kd"];
        if (k.contains("builder")) a.kd.builder = read_enum(k["builder"], "structure.kd.builder", parse_kd_builder);
        a.kd.max_depth = read(k, "max_depth", a.kd.max_depth, "structure.kd");
        a.kd.leaf_size = read(k, "leaf_size", a.kd.leaf_size, "structure.kd");
        a.kd.cost_trav = read(k, "cost_trav", a.kd.cost_trav, "structure.kd");
        a.kd.cost_isect = read(k, "cost_isect", a.kd.cost_isect, "structure.kd");
        a.kd.empty_bonus = read(k, "empty_bonus", a.kd.empty_bonus, "structure.kd");
        if (k.contains("clip")) a.kd.clip = read_enum(k["clip"], "structure.kd.clip", parse_clip_mode);
        a.kd.strict_cell = read(k, "strict_cell", a.kd.strict_cell, "structure.kd");
        a.kd.mailbox = read(k, "mailbox", a.kd.mailbox, "structure.kd");
    }
    if (j.contains("octree")) {
        const auto& o = j["octree"];
        a.octree.max_depth = read(o, "max_depth", a.octree.max_depth, "structure.octree");
        a.octree.leaf_size = read(o, "leaf_size", a.octree.leaf_size, "structure.octree");
        if (o.contains("clip")) a.octree.clip = read_enum(o["clip"], "structure.octree.clip", parse_clip_mode);
        a.octree.mailbox = read(o, "mailbox", a.octree.mailbox, "structure.octree");
    }
    if (j.contains("bsp")) {
        const auto& o = j["bsp"];
        a.bsp.max_depth = read(o, "max_depth", a.bsp.max_depth, "structure.bsp");
        a.bsp.leaf_size = read(o, "leaf_size", a.bsp.leaf_size, "structure.bsp");
        a.bsp.candidates = read(o, "candidates", a.bsp.candidates, "structure.bsp");
        a.bsp.mailbox = read(o, "mailbox", a.bsp.mailbox, "structure.bsp");
    }
    if (j.contains("triangle_test"))
        a.triangle_test = read_enum(j["triangle_test"], "structure.triangle_test", parse_triangle_test);
    a.leaf_size = read(j, "leaf_size", a.leaf_size, "structure");
    a.cost_trav = read(j, "cost_trav", a.cost_trav, "structure");
    a.cost_isect = read(j, "cost_isect", a.cost_isect, "structure");
    a.structure_file = read(j, "file", a.structure_file, "structure");
}

}  // namespace

nlohmann::json to_json(const AppState& s) {
    nlohmann::json j;
    j["scene"] = s.scene;
    j["structure"] = accel_config_json(s.accel);
    j["overlay"] = {{"show_structure", s.overlay.show_structure},
                    {"level_min", s.overlay.level_min},
                    {"level_max", s.overlay.level_max},
                    {"leaves_only", s.overlay.leaves_only},
                    {"mesh_opacity", s.overlay.mesh_opacity},
                    {"max_boxes", s.overlay.max_boxes}};
    if (s.camera)
        j["camera"] = {{"eye", vec3_json(s.camera->eye)},
                       {"target", vec3_json(s.camera->target)},
                       {"up", vec3_json(s.camera->up)},
                       {"fov", s.camera->fov_deg}};
    else
        j["camera"] = nullptr;
    j["view"] = {{"ui_scale", s.view.ui_scale},   {"light_theme", s.view.light_theme},
                 {"background", rgb_json(s.view.background)}, {"show_ui", s.view.show_ui},
                 {"show_help", s.view.show_help}, {"show_bounds", s.view.show_bounds},
                 {"mode", std::string(to_string(s.view.mode))},
                 {"draw_with", std::string(to_string(s.view.draw_with))},
                 {"right_view", std::string(to_string(s.view.right_view))},
                 {"left_view", std::string(to_string(s.view.left_view))}, {"heat_same_scale", s.view.heat_same_scale},
                 {"heat_rays", std::string(to_string(s.view.heat_rays))},
                 {"line_width", s.view.line_width}, {"fill_order", s.view.fill_order}, {"fill", s.view.fill},
                 {"ray_cast_by", std::string(to_string(s.view.ray_cast_by))},
                 {"slice", s.view.slice}, {"slice_axis", std::string(1, "xyz"[s.view.slice_axis])},
                 {"slice_at", s.view.slice_at}};
    j["refit_bvh"] = s.refit_bvh;
    j["light"] = {{"shadows", s.light.shadows},
                  {"reflections", s.light.reflections},
                  {"position", s.light.position ? vec3_json(*s.light.position) : nlohmann::json(nullptr)}};
    nlohmann::json b = {{"active", s.build_step.active}, {"step", s.build_step.step}};
    if (s.build_step.bins) b["bins"] = *s.build_step.bins;
    if (s.build_step.cost_trav) b["cost_trav"] = *s.build_step.cost_trav;
    if (s.build_step.cost_isect) b["cost_isect"] = *s.build_step.cost_isect;
    j["build_step"] = b;
    nlohmann::json stepper = {{"open", s.stepper.open}, {"step", s.stepper.step}, {"any_hit", s.stepper.any_hit}};
    if (s.stepper.ray)
        stepper["ray"] = {{"origin", {s.stepper.ray->origin.x, s.stepper.ray->origin.y, s.stepper.ray->origin.z}},
                          {"dir", {s.stepper.ray->dir.x, s.stepper.ray->dir.y, s.stepper.ray->dir.z}},
                          {"t_min", float_to_json(s.stepper.ray->t_min)},
                          {"t_max", float_to_json(s.stepper.ray->t_max)}};
    else
        stepper["ray"] = nullptr;
    if (s.stepper.pixel) stepper["pixel"] = {(*s.stepper.pixel)[0], (*s.stepper.pixel)[1]};
    j["stepper"] = stepper;
    j["nearest"] = {{"open", s.nearest.open},
                    {"point", s.nearest.point ? vec3_json(*s.nearest.point) : nlohmann::json(nullptr)},
                    {"step", s.nearest.step}};
    j["comparison"] = {{"open", s.comparison.open}};
    j["two_bvhs"] = {{"open", s.two_bvhs.open},
                     {"builders", {to_string(s.two_bvhs.builders[0]), to_string(s.two_bvhs.builders[1])}}};
    nlohmann::json scaling_structures = nlohmann::json::array();
    for (AccelType type : s.scaling.structures) scaling_structures.push_back(std::string(to_string(type)));
    j["scaling"] = {{"open", s.scaling.open},
                    {"max_triangles", s.scaling.max_triangles},
                    {"structures", scaling_structures}};
    return j;
}

Expected<AppState> app_state_from_json(const nlohmann::json& j) {
    AppState s;
    try {
        if (!j.is_object()) return Error{"state: expected a JSON object"};
        s.scene = read(j, "scene", s.scene, "");
        if (j.contains("structure")) read_accel(j["structure"], s.accel);
        s.refit_bvh = read(j, "refit_bvh", s.refit_bvh, "");
        if (j.contains("overlay")) {
            const auto& o = j["overlay"];
            s.overlay.show_structure = read(o, "show_structure", s.overlay.show_structure, "overlay");
            s.overlay.level_min = read(o, "level_min", s.overlay.level_min, "overlay");
            s.overlay.level_max = read(o, "level_max", s.overlay.level_max, "overlay");
            s.overlay.leaves_only = read(o, "leaves_only", s.overlay.leaves_only, "overlay");
            s.overlay.mesh_opacity = read(o, "mesh_opacity", s.overlay.mesh_opacity, "overlay");
            s.overlay.max_boxes = read(o, "max_boxes", s.overlay.max_boxes, "overlay");
            if (!(s.overlay.mesh_opacity >= 0.0f && s.overlay.mesh_opacity <= 1.0f))
                return Error{"overlay.mesh_opacity: must be between 0 and 1"};
        }
        if (j.contains("camera") && !j["camera"].is_null()) {
            const auto& c = j["camera"];
            CameraParams p;
            if (c.contains("eye")) p.eye = read_vec3(c["eye"], "camera.eye");
            if (c.contains("target")) p.target = read_vec3(c["target"], "camera.target");
            if (c.contains("up")) p.up = read_vec3(c["up"], "camera.up");
            p.fov_deg = read(c, "fov", p.fov_deg, "camera");
            if (auto err = validate(p)) return *err;
            s.camera = p;
        }
        if (j.contains("view")) {
            const auto& v = j["view"];
            s.view.ui_scale = read(v, "ui_scale", s.view.ui_scale, "view");
            if (!(s.view.ui_scale >= 0.5f && s.view.ui_scale <= 4.0f))
                return Error{"view.ui_scale: must be between 0.5 and 4"};
            s.view.light_theme = read(v, "light_theme", s.view.light_theme, "view");
            if (v.contains("background")) s.view.background = read_rgb(v["background"], "view.background");
            s.view.show_ui = read(v, "show_ui", s.view.show_ui, "view");
            s.view.show_help = read(v, "show_help", s.view.show_help, "view");
            s.view.show_bounds = read(v, "show_bounds", s.view.show_bounds, "view");
            s.view.line_width = read(v, "line_width", s.view.line_width, "view");
            if (!(s.view.line_width >= 1.0f && s.view.line_width <= 6.0f))
                return Error{"view.line_width: must be between 1 and 6 pixels"};
            if (v.contains("mode")) s.view.mode = read_named(v["mode"], "view.mode", kViewModeNames);
            if (v.contains("draw_with")) s.view.draw_with = read_named(v["draw_with"], "view.draw_with", kDrawWithNames);
            if (v.contains("right_view")) s.view.right_view = read_named(v["right_view"], "view.right_view", kRightViewNames);
            if (v.contains("left_view")) s.view.left_view = read_named(v["left_view"], "view.left_view", kLeftViewNames);
            s.view.heat_same_scale = read(v, "heat_same_scale", s.view.heat_same_scale, "view");
            if (v.contains("heat_rays")) s.view.heat_rays = read_named(v["heat_rays"], "view.heat_rays", kHeatRaysNames);
            s.view.fill_order = read(v, "fill_order", s.view.fill_order, "view");
            s.view.fill = read(v, "fill", s.view.fill, "view");
            if (v.contains("ray_cast_by"))
                s.view.ray_cast_by = read_named(v["ray_cast_by"], "view.ray_cast_by", kRayCastByNames);
            s.view.slice = read(v, "slice", s.view.slice, "view");
            if (v.contains("slice_axis")) {
                const std::string axis = read(v, "slice_axis", std::string("z"), "view");
                if (axis != "x" && axis != "y" && axis != "z") return Error{"view.slice_axis: x, y or z"};
                s.view.slice_axis = axis[0] - 'x';
            }
            s.view.slice_at = read(v, "slice_at", s.view.slice_at, "view");
            if (!(s.view.slice_at >= 0.0f && s.view.slice_at <= 1.0f)) return Error{"view.slice_at: must be between 0 and 1"};
            if (!(s.view.fill >= 0.0f && s.view.fill <= 1.0f)) return Error{"view.fill: must be between 0 and 1"};
        }
        if (j.contains("light")) {
            const auto& l = j["light"];
            s.light.shadows = read(l, "shadows", s.light.shadows, "light");
            s.light.reflections = read(l, "reflections", s.light.reflections, "light");
            if (l.contains("position") && !l["position"].is_null()) {
                s.light.position = read_vec3(l["position"], "light.position");
                if (!within_max_coordinate(*s.light.position))
                    return Error{"light.position: must be finite, each coordinate within 1e12"};
            }
        }
        if (j.contains("build_step")) {
            const auto& b = j["build_step"];
            BuildStepSettings& bs = s.build_step;
            bs.active = read(b, "active", bs.active, "build_step");
            bs.step = read(b, "step", bs.step, "build_step");
            if (bs.step < 0) return Error{"build_step.step: must be 0 or more"};
            bs.bins = read(b, "bins", bs.bins, "build_step");
            bs.cost_trav = read(b, "cost_trav", bs.cost_trav, "build_step");
            bs.cost_isect = read(b, "cost_isect", bs.cost_isect, "build_step");
            if (bs.bins && (*bs.bins < 2 || *bs.bins > 64)) return Error{"build_step.bins: must be between 2 and 64"};
            if (bs.cost_trav && !(*bs.cost_trav >= 0.0f)) return Error{"build_step.cost_trav: must be 0 or more"};
            if (bs.cost_isect && !(*bs.cost_isect > 0.0f)) return Error{"build_step.cost_isect: must be more than 0"};
        }
        if (j.contains("stepper")) {
            const auto& st = j["stepper"];
            s.stepper.open = read(st, "open", s.stepper.open, "stepper");
            s.stepper.step = read(st, "step", s.stepper.step, "stepper");
            s.stepper.any_hit = read(st, "any_hit", s.stepper.any_hit, "stepper");
            if (st.contains("ray") && !st["ray"].is_null()) {
                const auto& r = st["ray"];
                Ray ray;
                const Vec3d o = read_vec3(r.at("origin"), "stepper.ray.origin");
                const Vec3d d = read_vec3(r.at("dir"), "stepper.ray.dir");
                ray.origin = {float(o.x), float(o.y), float(o.z)};
                ray.dir = {float(d.x), float(d.y), float(d.z)};
                if (r.contains("t_min")) ray.t_min = read_float(r["t_min"], "stepper.ray.t_min");
                if (r.contains("t_max")) ray.t_max = read_float(r["t_max"], "stepper.ray.t_max");
                if (!(std::isfinite(ray.origin.x) && std::isfinite(ray.origin.y) && std::isfinite(ray.origin.z)))
                    return Error{"stepper.ray.origin: must be finite"};
                if (!(ray.dir.x != 0 || ray.dir.y != 0 || ray.dir.z != 0) ||
                    !(std::isfinite(ray.dir.x) && std::isfinite(ray.dir.y) && std::isfinite(ray.dir.z)))
                    return Error{"stepper.ray.dir: must be a finite, non-zero vector"};
                if (!(ray.t_min <= ray.t_max)) return Error{"stepper.ray: t_min must not exceed t_max"};
                s.stepper.ray = ray;
            }
            if (st.contains("pixel") && !st["pixel"].is_null()) {
                const auto& p = st["pixel"];
                if (!p.is_array() || p.size() != 2) return Error{"stepper.pixel: expected [x, y]"};
                // Pixels of an image at most 16384 wide and high, as `render` makes.
                s.stepper.pixel = std::array<int, 2>{read_whole(p[0], "stepper.pixel", 0, 16383),
                                                     read_whole(p[1], "stepper.pixel", 0, 16383)};
            }
        }
        if (j.contains("nearest")) {
            const auto& n = j["nearest"];
            s.nearest.open = read(n, "open", s.nearest.open, "nearest");
            s.nearest.step = read(n, "step", s.nearest.step, "nearest");
            if (n.contains("point") && !n["point"].is_null()) {
                s.nearest.point = read_vec3(n["point"], "nearest.point");
                if (!within_max_coordinate(*s.nearest.point))
                    return Error{"nearest.point: must be finite, each coordinate within 1e12"};
            }
        }
        if (j.contains("comparison")) s.comparison.open = read(j["comparison"], "open", s.comparison.open, "comparison");
        if (j.contains("two_bvhs")) {
            const auto& t = j["two_bvhs"];
            s.two_bvhs.open = read(t, "open", s.two_bvhs.open, "two_bvhs");
            if (t.contains("builders")) {
                const auto& b = t["builders"];
                if (!b.is_array() || b.size() != 2) throw std::runtime_error("two_bvhs.builders: expected two builder names");
                for (size_t i = 0; i < 2; ++i)
                    s.two_bvhs.builders[i] = read_enum(b[i], "two_bvhs.builders", parse_bvh_builder);
            }
        }
        if (j.contains("scaling")) {
            const auto& c = j["scaling"];
            s.scaling.open = read(c, "open", s.scaling.open, "scaling");
            s.scaling.max_triangles = read(c, "max_triangles", s.scaling.max_triangles, "scaling");
            if (!(s.scaling.max_triangles >= 1e4 && s.scaling.max_triangles <= 2e7))
                return Error{"scaling.max_triangles: must be between 10000 and 20000000"};
            if (c.contains("structures")) {
                const auto& list = c["structures"];
                if (!list.is_array() || list.empty())
                    throw std::runtime_error("scaling.structures: expected a list of structure names");
                s.scaling.structures.clear();
                for (const auto& name : list) {
                    const AccelType type = read_enum(name, "scaling.structures", parse_accel_type);
                    if (std::find(kScalingStructures.begin(), kScalingStructures.end(), type) ==
                        kScalingStructures.end())
                        return Error{"scaling.structures: " + std::string(to_string(type)) +
                                     " is not offered (bvh, kd, grid, octree)"};
                    if (std::find(s.scaling.structures.begin(), s.scaling.structures.end(), type) ==
                        s.scaling.structures.end())
                        s.scaling.structures.push_back(type);
                }
            }
        }
    } catch (const std::exception& e) {  // ours name the field; nlohmann's do not
        return Error{without_json_tag(e.what())};
    }
    return s;
}

Expected<AppState> load_app_state_file(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec)) return Error{path + ": is a directory, not a JSON file"};
    std::ifstream in(path);
    if (!in) return Error{path + ": cannot read (" + std::strerror(errno) + ")"};
    nlohmann::json json;
    try {
        json = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
        return Error{path + ": not valid JSON: " + without_json_tag(e.what())};  // "parse error at line 3, column 5: ..."
    }
    auto state = app_state_from_json(json);
    if (!state) return Error{path + ": " + state.error()};
    const std::string& scene = state->scene;
    if (scene.rfind("builtin:", 0) != 0 && fs::path(scene).is_relative()) {
        const fs::path beside = fs::path(path).parent_path() / scene;
        if (fs::is_regular_file(beside, ec)) state->scene = beside.lexically_normal().string();
    }
    // A structure file, likewise: beside the preset when it is there.
    std::string& tree = state->accel.structure_file;
    if (!tree.empty() && fs::path(tree).is_relative()) {
        const fs::path beside = fs::path(path).parent_path() / tree;
        if (fs::is_regular_file(beside, ec)) tree = beside.lexically_normal().string();
    }
    return state;
}

Expected<AppState> load_app_state_file_checked(const std::string& path) {
    auto state = load_app_state_file(path);
    if (!state) return state;
    if (auto err = validate(state->accel)) return Error{path + ": structure: " + err->message};
    return state;
}

Vec3d light_position(const LightSettings& light, const Aabb& bounds) {
    return light.position ? *light.position : to_double(default_light(bounds));
}

std::optional<Lighting> lighting_for(const LightSettings& light, const Mesh& mesh, const Aabb& bounds) {
    if (!light.point_light()) return std::nullopt;
    Lighting lighting;
    lighting.light = to_float(light_position(light, bounds));
    lighting.shadows = light.shadows;
    lighting.reflections = light.reflections;
    if (light.reflections) lighting.mirror = mesh.mirror;
    return lighting;
}

}  // namespace accelviz

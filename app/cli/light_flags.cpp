#include "app/cli/light_flags.h"

#include <cmath>

#include "core/render/camera.h"
#include "core/geometry/mesh.h"

namespace accelviz::cli {

void add_light_flags(CLI::App& app, LightFlags& flags) {
    app.add_option("--shadows", flags.shadows,
                   "on: the ray caster lights the scene with a point light (--light) and traces a shadow ray from "
                   "every hit to it, the any-hit query through the structure (it stops at the first occluder). "
                   "Default: the preset's, else off")
        ->check(CLI::IsMember({"on", "off"}));
    app.add_option("--reflections", flags.reflections,
                   "on: the ray caster lights the scene with a point light and traces one reflection ray (closest "
                   "hit) from every mirror triangle (builtin:cornell-mirror's tall block). Default: the preset's, "
                   "else off")
        ->check(CLI::IsMember({"on", "off"}));
    app.add_option("--light", flags.light,
                   "The point light's position X,Y,Z (default: the preset's, else inside the scene's box, near its "
                   "top and front right); given alone, the scene is lit by it without shadows");
    app.add_option("--mirror", flags.mirror,
                   "Make object N of the OBJ file a mirror for --reflections on (its objects: the faces between its o "
                   "and g statements, numbered from 0 in file order; faces before the first statement are object 0)")
        ->check(CLI::Range(0, 1000000));
}

Expected<std::string> apply_mirror_flag(const LightFlags& flags, const std::string& scene) {
    if (!flags.mirror) return scene;
    if (scene.rfind("builtin:", 0) == 0)
        return Error{"--mirror picks an object of an OBJ file, not of " + scene +
                     " (builtin:cornell-mirror has its mirror already)"};
    return "builtin:mirror?mesh=" + scene + "&object=" + std::to_string(*flags.mirror);
}

Expected<LightSettings> apply_light_flags(const LightFlags& flags, LightSettings light) {
    if (!flags.shadows.empty()) light.shadows = flags.shadows == "on";
    if (!flags.reflections.empty()) light.reflections = flags.reflections == "on";
    if (!flags.light.empty()) {
        auto p = parse_vec3(flags.light);
        if (!p) return Error{"--light: " + p.error()};
        if (!within_max_coordinate(*p))
            return Error{"--light " + flags.light + ": each coordinate must be finite and within 1e12"};
        light.position = *p;
    }
    return light;
}

}  // namespace accelviz::cli

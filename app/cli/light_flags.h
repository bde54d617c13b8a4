#pragma once
/// --shadows, --reflections and --light: the ray caster's point light (LightSettings),
/// on the commands that draw (render, the window). Given flags replace the preset's.

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "app/gui/app_state.h"

namespace accelviz::cli {

struct LightFlags {
    std::string shadows;      ///< "on" | "off" | "" (not given)
    std::string reflections;  ///< "on" | "off" | ""
    std::string light;        ///< "X,Y,Z" | ""
    std::optional<int> mirror;  ///< --mirror N: object N of the OBJ file is a mirror
};

void add_light_flags(CLI::App& app, LightFlags& flags);
/// The flags given laid over `state.light`; a one-line error for a bad --light.
Expected<LightSettings> apply_light_flags(const LightFlags& flags, LightSettings light);
/// `scene` with --mirror N applied: builtin:mirror?mesh=SCENE&object=N (an OBJ file's
/// object N made a mirror); `scene` itself without the flag. An error for a built-in.
Expected<std::string> apply_mirror_flag(const LightFlags& flags, const std::string& scene);

}  // namespace accelviz::cli

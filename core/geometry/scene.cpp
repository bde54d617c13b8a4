// load_scene: the one entry point the CLI and the window use for a scene source.
#include "core/geometry/scene.h"

namespace accelviz {

Expected<Mesh> load_scene(const std::string& source) {
    constexpr std::string_view kBuiltinPrefix = "builtin:";
    if (source.empty()) return Error{"no scene given (want an OBJ file or builtin:NAME)"};
    if (source.starts_with(kBuiltinPrefix)) return make_builtin(source.substr(kBuiltinPrefix.size()));
    return load_obj(source);
}

}  // namespace accelviz

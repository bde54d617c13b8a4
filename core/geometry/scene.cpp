#include "core/geometry/scene.h"

namespace accelviz {

// Placeholder until the scene loaders land.
Expected<Mesh> load_obj(const std::string& path) { return Error{path + ": OBJ loading not implemented yet"}; }
Expected<Mesh> make_builtin(const std::string& spec) {
    if (spec == "cube") {
        Mesh m; m.name = "builtin:cube";
        m.add_triangle({-1,-1,1},{1,-1,1},{1,1,1});
        return m;
    }
    return Error{"unknown built-in scene '" + spec + "'"};
}
const std::vector<BuiltinInfo>& builtin_scenes() { static std::vector<BuiltinInfo> v; return v; }
Expected<Mesh> load_scene(const std::string& source) {
    if (source.rfind("builtin:", 0) == 0) return make_builtin(source.substr(8));
    return load_obj(source);
}

}  // namespace accelviz

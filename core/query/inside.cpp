#include "core/query/inside.h"

#include <cmath>

namespace accelviz {

std::array<Vec3, 3> parity_directions() {
    // Fixed, so that answers repeat; not along an axis, a face diagonal or the main
    // diagonals, where the built-in and scanned meshes' edges tend to line up.
    auto unit = [](double x, double y, double z) {
        const double l = std::sqrt(x * x + y * y + z * z);
        return Vec3{float(x / l), float(y / l), float(z / l)};
    };
    return {unit(0.8317, 0.3129, 0.4587), unit(-0.2713, 0.9107, 0.3119), unit(0.1931, -0.4217, 0.8861)};
}

}  // namespace accelviz

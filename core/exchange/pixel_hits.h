#pragma once
/// A traversal's per-pixel answers from a file (a student's ray caster: pixel,
/// triangle id, t) against the right ones, so that `accelviz check --hits` can list
/// the pixels where a student's traversal goes wrong.

#include <cstdint>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/mesh.h"
#include "core/render/camera.h"
#include "core/util/expected.h"

namespace accelviz {

/// One line of the file: pixel (x, y) (0, 0 = top left, the camera contract), and the
/// closest hit found there, or a miss (tri == Hit::kNoHit).
struct PixelHit {
    int x = 0, y = 0;
    uint32_t tri = Hit::kNoHit;
    float t = 0;
};

/// Reads CSV lines "x,y,triangle,t" (a first line that is not numbers is a header;
/// a triangle of -1 is a miss, its t ignored; blank lines skipped). Pixels must lie
/// in a width x height image. Errors name the line.
Expected<std::vector<PixelHit>> parse_pixel_hits(const std::string& text, int width, int height);

/// A pixel whose answer differs from the right one.
struct PixelDisagreement {
    PixelHit yours;
    Hit right;
};

struct PixelHitComparison {
    uint64_t pixels = 0;  ///< lines compared
    uint64_t agree = 0;
    uint64_t ties = 0;    ///< of agree: another triangle at the same t (a ray through a shared edge)
    std::vector<PixelDisagreement> differ;  ///< every pixel that disagrees, in file order
};

/// Relative tolerance on t: a student's arithmetic (double, another formula) lands
/// within this of ours on the same triangle.
inline constexpr double kPixelHitRelativeT = 1e-4;

/// Each pixel's ray through `camera` traced by `reference` (a structure over `mesh`,
/// exact against brute force), compared with the file's answer: the same triangle
/// (or a miss), t within kPixelHitRelativeT. Another triangle counts as a tie, not a
/// disagreement, when the ray really meets it at that same t (a ray through an edge
/// two triangles share; checked in double with 1e-6 of slack on the barycentrics).
PixelHitComparison compare_pixel_hits(const std::vector<PixelHit>& hits, const Camera& camera, const Mesh& mesh,
                                      const Accelerator& reference);

}  // namespace accelviz

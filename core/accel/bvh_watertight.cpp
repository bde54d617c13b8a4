// The BVH's walks with the watertight triangle test (see the end of bvh.h).
#include "core/accel/bvh.h"

namespace accelviz {

ACCELVIZ_BVH_TRAVERSALS(, Watertight)

}  // namespace accelviz

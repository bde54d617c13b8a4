#pragma once
/// Triangle against axis-aligned box, the two questions a space-partitioning
/// build asks (lecture: 均匀网格 "每个格子保存重叠的图像基元", KD 树 straddling
/// triangles):
///   - does the closed triangle touch the closed box?   (separating axes)
///   - what is the box of the part of the triangle inside the box? (polygon clipping)
/// Both work in double precision and err on the side of "yes, it overlaps":
/// callers add a safety margin (see reference_padding) on top anyway.

#include "core/math/aabb.h"

namespace accelviz {

/// Separating axis test (Akenine-Möller 2001, "Fast 3D triangle-box overlap
/// testing"): the triangle and the box are disjoint iff one of 13 axes separates
/// their projections: the 3 box normals, the triangle normal and the 9 cross
/// products of a box normal with a triangle edge. Touching counts as overlap.
/// A degenerate triangle (a segment or a point) is tested as such: its zero
/// normal separates nothing, the remaining axes still do.
bool triangle_overlaps_box(Vec3 p0, Vec3 p1, Vec3 p2, const Aabb& box);

/// triangle_overlaps_box for one triangle against many boxes (an octree cell's
/// octants): the ten axes that do not depend on the box (the triangle's normal and
/// the nine box axis × edge crosses) and the triangle's extent along each are worked
/// out once; a box then costs its centre's and half-size's projections on them.
/// Absolute coordinates, in double: its answers may differ from
/// triangle_overlaps_box's only for boxes within ~1e-15 of the coordinates' magnitude
/// of touching, which the callers' padding (reference_padding, 2^-14 of that
/// magnitude) covers many times over.
class TriangleAxes {
public:
    TriangleAxes(Vec3 p0, Vec3 p1, Vec3 p2);
    bool overlaps(const Aabb& box) const;

private:
    /// Ten axes and two zero ones (which separate nothing) for whole vector registers:
    /// the box test runs over all twelve without a branch.
    static constexpr int kAxes = 12;
    double x_[kAxes], y_[kAxes], z_[kAxes];  ///< the axes, by component
    double lo_[kAxes], hi_[kAxes];           ///< the triangle's extent along each
    double box_lo_[3], box_hi_[3];           ///< its bounds (the three box normals)
};

/// Bounds of triangle ∩ box: the triangle polygon is clipped against the six
/// planes of the box (Sutherland–Hodgman) and the remaining polygon's bounds are
/// rounded outwards to float. Empty Aabb if the triangle misses the box. For a
/// triangle straddling a KD split plane this is the tight box of its part on one
/// side ("perfect splits", Wald & Havran 2006), much smaller than box ∩ box.
Aabb clip_triangle_to_box(Vec3 p0, Vec3 p1, Vec3 p2, const Aabb& box);

/// The part of a triangle that clipping leaves: a convex polygon, in double
/// precision (Sutherland–Hodgman). clip_triangle_to_box is of_triangle, clip_to,
/// bounds_within; a tree splitting a triangle among several children clips it to
/// the node once and then cuts the polygon at the split planes (keep_side).
struct ClippedPolygon {
    /// A triangle cut by the six planes of a box and three more planes: 3 + 9 corners.
    static constexpr int kMaxCorners = 12;
    double v[kMaxCorners][3];
    int count = 0;  ///< 0: nothing left

    static ClippedPolygon of_triangle(Vec3 p0, Vec3 p1, Vec3 p2);
    /// This polygon becomes `other` (its corners only, not the whole array).
    void copy_from(const ClippedPolygon& other) {
        count = other.count;
        for (int i = 0; i < count; ++i)
            for (int k = 0; k < 3; ++k) v[i][k] = other.v[i][k];
    }
    /// Keeps the part with x_axis >= plane (keep_above) or <= plane (each cut adds at
    /// most one corner: nine cuts of a triangle in all).
    void keep_side(int axis, double plane, bool keep_above) {
        // Each corner's signed distance: sign * (x_a - plane) >= 0 is kept. A plane with
        // every corner on the kept side changes nothing (most planes of a cell that a
        // triangle straddles on one axis only): no pass, and no call.
        const double sign = keep_above ? 1.0 : -1.0;
        int inside = 0;
        for (int i = 0; i < count; ++i) inside += sign * (v[i][axis] - plane) >= 0 ? 1 : 0;
        if (inside == count) return;
        if (inside == 0) count = 0;
        else cut(axis, plane, sign);
    }
    /// Keeps the part inside `box`: its six planes, lo then hi, x then y then z.
    void clip_to(const Aabb& box);
    /// The polygon's bounds rounded outwards to float, clamped to `box` (the box it
    /// was clipped to, which rounding may overstep); empty if nothing is left.
    Aabb bounds_within(const Aabb& box) const;
    /// What keep_side(axis, plane, keep_above), then bounds_within(box) give, bit for
    /// bit, without changing this polygon: one pass, no copy.
    Aabb side_bounds_within(int axis, double plane, bool keep_above, const Aabb& box) const;

private:
    /// keep_side's pass (Sutherland–Hodgman) for a plane with corners on both sides.
    void cut(int axis, double plane, double sign);
};

/// The safety margin of every space-partitioning structure (grid, KD tree,
/// octree). A triangle is referenced by every cell it comes within `padding` of,
/// not only by the cells it touches. Why: a traversal computes cell boundaries
/// t = (plane - origin) / dir and Möller–Trumbore computes the hit's t, each with
/// rounding error; the cell the walk is in when it reaches a hit's t may then be a
/// neighbour of the cell that holds the hit point. With the margin, that
/// neighbour references the triangle too, so the walk still finds it, and the
/// answer equals brute force's. The margin is 2^-14 of the scene's largest
/// coordinate magnitude: about 500 float ulps of the coordinates, far above
/// the rounding error of rays whose origin lies within ~100 scene sizes, and far
/// below a cell's size for any scene that needs a structure.
float reference_padding(const Aabb& scene_bounds);

/// `box` grown by `pad` on every side.
inline Aabb padded(const Aabb& box, float pad) {
    return {box.lo - Vec3{pad, pad, pad}, box.hi + Vec3{pad, pad, pad}};
}

/// Intersection of two boxes (empty if disjoint).
inline Aabb intersection(const Aabb& a, const Aabb& b) { return {max(a.lo, b.lo), min(a.hi, b.hi)}; }

}  // namespace accelviz

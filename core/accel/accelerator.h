#pragma once
/// The common face of every acceleration structure, for code that works with
/// "whatever structure the user picked" (ray caster, bench, trace, the window).
///
/// Each concrete structure writes its traversal ONCE, as a template over an
/// observer, and AcceleratorFor<> (below) instantiates it three times:
/// NoObserver (fast path), CountingObserver (heat maps) and RecordingObserver
/// (trace, stepper); the same for the any-hit query of shadow rays. So what the stepper shows is what renders the image.

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "core/accel/accel_type.h"
#include "core/geometry/mesh.h"
#include "core/traversal/observers.h"

namespace accelviz {

class Accelerator {
public:
    virtual ~Accelerator() = default;
    virtual AccelType type() const = 0;
    /// "naive", "bvh", "grid", "kd", "octree", "bsp" (to_string(type())).
    virtual std::string name() const = 0;
    /// Closest hit in [ray.t_min, ray.t_max].
    virtual Hit intersect_closest(const Ray& ray) const = 0;
    virtual Hit intersect_closest(const Ray& ray, CountingObserver& obs) const = 0;
    virtual Hit intersect_closest(const Ray& ray, RecordingObserver& obs) const = 0;
    /// Any hit in [ray.t_min, ray.t_max] (shadow rays): stops at the first one.
    virtual bool intersect_any(const Ray& ray) const = 0;
    virtual bool intersect_any(const Ray& ray, CountingObserver& obs) const = 0;
    virtual bool intersect_any(const Ray& ray, RecordingObserver& obs) const = 0;
    /// Which ray-triangle test every traversal runs.
    virtual TriangleTestKind triangle_test() const = 0;
    /// Build configuration and statistics, as bench and the Stats panel show them.
    virtual nlohmann::json config() const { return nlohmann::json::object(); }
    virtual nlohmann::json stats() const { return nlohmann::json::object(); }
};

/// Adapts a structure S that provides
///   template <class Obs> Hit intersect_closest(const Ray&, Obs&) const;
///   template <class Obs> bool intersect_any(const Ray&, Obs&) const;
///   static constexpr AccelType kType;
///   std::string name() const; json config() const; json stats() const;
/// to the Accelerator interface.
template <class S>
class AcceleratorFor final : public Accelerator {
public:
    explicit AcceleratorFor(S structure) : s_(std::move(structure)) {}
    AccelType type() const override { return S::kType; }
    std::string name() const override { return s_.name(); }
    Hit intersect_closest(const Ray& ray) const override {
        NoObserver obs;
        return s_.intersect_closest(ray, obs);
    }
    Hit intersect_closest(const Ray& ray, CountingObserver& obs) const override {
        return s_.intersect_closest(ray, obs);
    }
    Hit intersect_closest(const Ray& ray, RecordingObserver& obs) const override {
        return s_.intersect_closest(ray, obs);
    }
    bool intersect_any(const Ray& ray) const override {
        NoObserver obs;
        return s_.intersect_any(ray, obs);
    }
    bool intersect_any(const Ray& ray, CountingObserver& obs) const override { return s_.intersect_any(ray, obs); }
    bool intersect_any(const Ray& ray, RecordingObserver& obs) const override { return s_.intersect_any(ray, obs); }
    TriangleTestKind triangle_test() const override { return s_.triangle_test; }
    nlohmann::json config() const override { return s_.config(); }
    nlohmann::json stats() const override { return s_.stats(); }
    const S& structure() const { return s_; }

private:
    S s_;
};

/// The structure behind `accel` if it is an S (a Bvh, a KdTree, ...), else nullptr:
/// for the code that draws or inspects one kind of structure in its own way.
template <class S>
const S* structure_if(const Accelerator& accel) {
    const auto* adapted = dynamic_cast<const AcceleratorFor<S>*>(&accel);
    return adapted ? &adapted->structure() : nullptr;
}

}  // namespace accelviz

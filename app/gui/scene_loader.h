#pragma once
/// Loading a scene and building its structure, off the UI thread.
///
/// The UI thread never loads or builds (docs/architecture.md, "Threads"): it hands
/// a request to the worker, keeps drawing (with a "loading..." indicator), and
/// swaps in the immutable result when it is ready. A newer request supersedes an
/// older one: the older one is cancelled (it stops at its next check; a file read
/// in progress finishes first) and its result dropped. cancel() (the Cancel button)
/// stops the work and gives the error "cancelled".

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/accel/factory.h"
#include "core/exchange/structure_check.h"
#include "core/geometry/mesh.h"
#include "core/util/expected.h"
#include "core/util/work_progress.h"

namespace accelviz {

/// A scene and its structure, immutable once published (shared with the UI).
struct LoadedScene {
    std::string source;       ///< what was asked for: "builtin:cube" or a path
    /// Shared between the scenes a rebuild makes from it (a new structure, same mesh).
    std::shared_ptr<const Mesh> mesh;
    Aabb bounds;              ///< mesh->bounds()
    AccelConfig accel_config;
    std::shared_ptr<const Accelerator> accel;  ///< built over *mesh
    double load_seconds = 0;
    double build_seconds = 0;  ///< the build, or for a refitted scene the refit
    bool refitted = false;     ///< the structure is an earlier time's BVH refitted to this mesh
    std::optional<std::string> degenerate_note;  ///< "k of N triangles have zero area ..." (degenerate_note)
    /// The structure file read when accel_config.structure_file is set (then `accel` is
    /// its structure, or brute force when the file is not valid); null otherwise.
    std::shared_ptr<const CheckedStructureFile> structure_file;
};

using LoadResult = Expected<std::shared_ptr<const LoadedScene>>;

/// Loads `source` (load_scene) and builds `config` over it, on the calling
/// thread. `on_stage` (if set) hears "Loading ..." / "Building ..." as work starts;
/// `progress` (if set) counts each stage and may cancel it.
LoadResult load_and_build(const std::string& source, const AccelConfig& config,
                          const std::function<void(const std::string&)>& on_stage = {},
                          WorkProgress* progress = nullptr);

/// With `refit` (AppState::refit_bvh): the time a moving scene at `source` is refitted
/// from when it is loaded, t = 0, if `source` is a later time and `config` a binary
/// BVH; none otherwise (then it is built).
std::optional<std::string> refit_start(const std::string& source, const AccelConfig& config, bool refit);

/// load_and_build, or, with a refit start, that time built and its BVH refitted to
/// `source` (what the window shows after playing from t = 0 with "Refit the BVH").
LoadResult load_and_build_or_refit(const std::string& source, const AccelConfig& config, bool refit);

/// Builds `config` over the mesh of `scene` (no reloading): the new scene shares
/// the mesh and keeps its source and load time.
LoadResult rebuild(const LoadedScene& scene, const AccelConfig& config,
                   const std::function<void(const std::string&)>& on_stage = {},
                   WorkProgress* progress = nullptr);

/// A moving scene's next time: loads `source` (the same triangles as `previous`,
/// moved) and refits `previous`'s binary BVH to it (refit_accelerator) rather than
/// building anew; any other structure, or other triangles, is built as by
/// load_and_build. The new scene says `refitted`.
LoadResult load_and_refit(const std::string& source, const LoadedScene& previous,
                          const std::function<void(const std::string&)>& on_stage = {},
                          WorkProgress* progress = nullptr);

/// Whether `result` is the error of work that was cancelled.
bool was_cancelled(const LoadResult& result);

class SceneLoader {
public:
    SceneLoader();
    /// Waits for the running job (if any) to finish.
    ~SceneLoader();
    SceneLoader(const SceneLoader&) = delete;
    SceneLoader& operator=(const SceneLoader&) = delete;

    /// Asks for `source` built with `config`; replaces a request not started yet.
    void request(const std::string& source, const AccelConfig& config);
    /// Asks for a new structure over the mesh of `scene` (a parameter changed).
    void request_rebuild(std::shared_ptr<const LoadedScene> scene, const AccelConfig& config);
    /// Asks for `source`, a later time of `scene`'s moving scene, with `scene`'s BVH
    /// refitted to it (load_and_refit).
    void request_refit(const std::string& source, std::shared_ptr<const LoadedScene> scene);
    /// Asks for `source`, a moving scene's time, with the BVH of `earlier` (another time
    /// of it, built with `config`) refitted to it: what a preset of a refitted time shows.
    void request_refit_from(const std::string& earlier, const std::string& source, const AccelConfig& config);
    /// Stops the running request and drops a waiting one; the running one's result
    /// is then the error "cancelled" (was_cancelled), unless it had finished.
    void cancel();
    /// The result of the newest request, once, when it has finished.
    std::optional<LoadResult> take_result();
    /// True when a result waits for take_result().
    bool has_result() const;
    /// True while a request is waiting or running.
    bool busy() const;
    /// What the worker is doing ("Loading bunny.obj"), for the status line.
    std::string activity() const;
    /// Seconds since the newest request was made (0 when idle).
    double busy_seconds() const;
    /// How far the running stage (activity()) has got, in [0, 1] (0 when idle).
    double stage_fraction() const;
    /// Called on the worker thread when a result is ready (e.g. to wake up a
    /// window waiting for events). Set before the first request.
    std::function<void()> on_finished;

private:
    struct Request {
        uint64_t id;
        std::string source;
        AccelConfig config;
        std::shared_ptr<const LoadedScene> rebuild_of;  ///< set: rebuild over this scene's mesh
        std::shared_ptr<const LoadedScene> refit_of;    ///< set: load source, refit this scene's BVH to it
        std::string refit_from;  ///< set: build this source (an earlier time), then refit it to `source`
    };
    /// Queues `request`, cancelling the running one (call with mutex_ held).
    void replace_request(Request request);
    void run();

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::optional<Request> pending_;
    std::optional<LoadResult> finished_;
    uint64_t newest_id_ = 0;
    bool running_ = false;
    bool quit_ = false;
    std::string activity_;
    /// The running request's progress (null when idle): the UI reads it, cancel() sets it.
    std::shared_ptr<WorkProgress> running_progress_;
    bool cancelled_by_user_ = false;  ///< cancel() stopped the running request
    std::chrono::steady_clock::time_point requested_at_;
    std::thread worker_;  ///< last member: starts after the others exist
};

}  // namespace accelviz

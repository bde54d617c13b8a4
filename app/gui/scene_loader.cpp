#include "app/gui/scene_loader.h"

#include "core/exchange/structure_check.h"
#include "core/geometry/scene.h"

namespace accelviz {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// "bunny.obj" for "/work/shared/assets/bunny.obj"; builtins unchanged.
std::string short_name(const std::string& source) {
    const size_t slash = source.find_last_of('/');
    return source.rfind("builtin:", 0) == 0 || slash == std::string::npos ? source : source.substr(slash + 1);
}

/// A scene with `source`'s mesh loaded and no structure yet.
Expected<std::shared_ptr<LoadedScene>> load_mesh(const std::string& source, const AccelConfig& config,
                                                 const std::function<void(const std::string&)>& on_stage,
                                                 WorkProgress* progress) {
    auto scene = std::make_shared<LoadedScene>();
    scene->source = source;
    scene->accel_config = config;
    if (on_stage) on_stage("Loading " + short_name(source));
    auto start = std::chrono::steady_clock::now();
    auto mesh = load_scene(source, default_mesh_cache(), progress);
    if (!mesh) return Error{mesh.error()};
    if (cancelled(progress)) return WorkProgress::cancelled_error();
    scene->mesh = std::make_shared<const Mesh>(std::move(*mesh));
    scene->bounds = scene->mesh->bounds();
    scene->degenerate_note = degenerate_note(*scene->mesh);
    scene->load_seconds = seconds_since(start);
    return scene;
}

}  // namespace

LoadResult load_and_build(const std::string& source, const AccelConfig& config,
                          const std::function<void(const std::string&)>& on_stage, WorkProgress* progress) {
    auto scene = load_mesh(source, config, on_stage, progress);
    if (!scene) return Error{scene.error()};
    return rebuild(**scene, config, on_stage, progress);
}

std::optional<std::string> refit_start(const std::string& source, const AccelConfig& config, bool refit) {
    if (!refit || config.type != AccelType::Bvh || config.bvh.width != 2 || !config.structure_file.empty()) return {};
    const std::optional<double> t = scene_time(source);
    if (!t || *t == 0.0) return {};
    auto start = scene_at_time(source, 0.0);
    if (!start) return {};
    return *start;
}

LoadResult load_and_build_or_refit(const std::string& source, const AccelConfig& config, bool refit) {
    const std::optional<std::string> start = refit_start(source, config, refit);
    if (!start) return load_and_build(source, config);
    LoadResult earlier = load_and_build(*start, config);
    if (!earlier) return earlier;
    return load_and_refit(source, **earlier);
}

LoadResult load_and_refit(const std::string& source, const LoadedScene& previous,
                          const std::function<void(const std::string&)>& on_stage, WorkProgress* progress) {
    auto scene = load_mesh(source, previous.accel_config, on_stage, progress);
    if (!scene) return Error{scene.error()};
    LoadedScene& next = **scene;
    // A structure from a file is read again (and checked against the moved mesh), not refitted.
    if (!previous.accel || !previous.mesh || previous.mesh->indices != next.mesh->indices ||
        !previous.accel_config.structure_file.empty())
        return rebuild(next, previous.accel_config, on_stage, progress);
    if (on_stage) on_stage("Refitting the BVH");
    const auto start = std::chrono::steady_clock::now();
    auto accel = refit_accelerator(*previous.accel, *next.mesh);
    if (!accel) return rebuild(next, previous.accel_config, on_stage, progress);  // not a binary BVH: build
    next.accel = std::move(*accel);
    next.build_seconds = seconds_since(start);
    next.refitted = true;
    return std::shared_ptr<const LoadedScene>(std::move(*scene));
}

LoadResult rebuild(const LoadedScene& from, const AccelConfig& config,
                   const std::function<void(const std::string&)>& on_stage, WorkProgress* progress) {
    auto scene = std::make_shared<LoadedScene>();
    scene->source = from.source;
    scene->mesh = from.mesh;
    scene->bounds = from.bounds;
    scene->degenerate_note = from.degenerate_note;
    scene->load_seconds = from.load_seconds;
    scene->accel_config = config;
    start_stage(progress, 0);
    const auto start = std::chrono::steady_clock::now();
    if (!config.structure_file.empty()) {
        // A structure from a file: read and checked, never trusted. Valid: our traversal
        // runs through it. Not valid: rays go through brute force, and the overlay draws
        // the file's nodes with the faulty ones red.
        if (on_stage) on_stage("Reading " + short_name(config.structure_file));
        auto crc = mesh_crc32(from.source, *scene->mesh);
        if (!crc) return Error{crc.error()};
        auto checked = read_and_check_structure(config.structure_file, *scene->mesh, *crc);
        if (!checked) return Error{checked.error()};
        scene->structure_file = std::make_shared<const CheckedStructureFile>(std::move(*checked));
        scene->accel_config.type = scene->structure_file->file->type;
        scene->accel = scene->structure_file->accel;
        if (!scene->accel) {
            AccelConfig naive;
            naive.type = AccelType::Naive;
            scene->accel = *build_accelerator(*scene->mesh, naive);
        }
        scene->build_seconds = seconds_since(start);
        return std::shared_ptr<const LoadedScene>(std::move(scene));
    }
    if (on_stage) on_stage("Building " + std::string(to_string(config.type)));
    auto accel = build_accelerator(*scene->mesh, config, progress);
    if (!accel) return Error{accel.error()};
    scene->accel = std::move(*accel);
    scene->build_seconds = seconds_since(start);
    return std::shared_ptr<const LoadedScene>(std::move(scene));
}

bool was_cancelled(const LoadResult& result) {
    return !result && result.error() == WorkProgress::cancelled_error().message;
}

SceneLoader::SceneLoader() : worker_([this] { run(); }) {}

SceneLoader::~SceneLoader() {
    {
        std::lock_guard lock(mutex_);
        quit_ = true;
        pending_.reset();
        if (running_progress_) running_progress_->cancel();
    }
    wake_.notify_all();
    worker_.join();
}

void SceneLoader::replace_request(Request request) {
    pending_ = std::move(request);
    finished_.reset();  // an older result is no longer wanted
    if (running_progress_) running_progress_->cancel();
    cancelled_by_user_ = false;
    requested_at_ = std::chrono::steady_clock::now();
    activity_ = "Waiting";
}

void SceneLoader::request(const std::string& source, const AccelConfig& config) {
    {
        std::lock_guard lock(mutex_);
        replace_request(Request{++newest_id_, source, config, nullptr, nullptr, {}});
    }
    wake_.notify_all();
}

void SceneLoader::request_rebuild(std::shared_ptr<const LoadedScene> scene, const AccelConfig& config) {
    {
        std::lock_guard lock(mutex_);
        const std::string source = scene->source;
        replace_request(Request{++newest_id_, source, config, std::move(scene), nullptr, {}});
    }
    wake_.notify_all();
}

void SceneLoader::request_refit(const std::string& source, std::shared_ptr<const LoadedScene> scene) {
    {
        std::lock_guard lock(mutex_);
        const AccelConfig config = scene->accel_config;
        replace_request(Request{++newest_id_, source, config, nullptr, std::move(scene), {}});
    }
    wake_.notify_all();
}

void SceneLoader::request_refit_from(const std::string& earlier, const std::string& source,
                                     const AccelConfig& config) {
    {
        std::lock_guard lock(mutex_);
        Request request{++newest_id_, source, config, nullptr, nullptr, {}};
        request.refit_from = earlier;
        replace_request(std::move(request));
    }
    wake_.notify_all();
}

void SceneLoader::cancel() {
    std::lock_guard lock(mutex_);
    const bool was_waiting = pending_.has_value();
    pending_.reset();
    if (running_) {
        // The worker hands over the "cancelled" error when the work stops.
        if (running_progress_) running_progress_->cancel();
        cancelled_by_user_ = true;
    } else if (was_waiting) {
        finished_ = LoadResult(WorkProgress::cancelled_error());
        activity_.clear();
        if (on_finished) on_finished();
    }
}

std::optional<LoadResult> SceneLoader::take_result() {
    std::lock_guard lock(mutex_);
    std::optional<LoadResult> result = std::move(finished_);
    finished_.reset();
    return result;
}

bool SceneLoader::has_result() const {
    std::lock_guard lock(mutex_);
    return finished_.has_value();
}

bool SceneLoader::busy() const {
    std::lock_guard lock(mutex_);
    return pending_.has_value() || running_;
}

std::string SceneLoader::activity() const {
    std::lock_guard lock(mutex_);
    // A stage inside the step says what it is ("Loading bunny.obj: writing the cache copy").
    const char* label = running_progress_ ? running_progress_->stage_label() : nullptr;
    return label ? activity_ + ": " + label : activity_;
}

double SceneLoader::stage_fraction() const {
    std::lock_guard lock(mutex_);
    return running_progress_ ? running_progress_->fraction() : 0.0;
}

double SceneLoader::busy_seconds() const {
    std::lock_guard lock(mutex_);
    return pending_ || running_ ? seconds_since(requested_at_) : 0.0;
}

void SceneLoader::run() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this] { return quit_ || pending_.has_value(); });
        if (quit_) return;
        Request request = std::move(*pending_);
        pending_.reset();
        running_ = true;
        cancelled_by_user_ = false;
        auto progress = std::make_shared<WorkProgress>();
        running_progress_ = progress;
        lock.unlock();

        auto on_stage = [this](const std::string& what) {
            std::lock_guard stage_lock(mutex_);
            activity_ = what;
        };
        if (!request.refit_from.empty()) {  // the earlier time built first, then refitted from below
            LoadResult earlier = load_and_build(request.refit_from, request.config, on_stage, progress.get());
            if (earlier) request.refit_of = *earlier;
        }
        LoadResult result = request.rebuild_of ? rebuild(*request.rebuild_of, request.config, on_stage, progress.get())
                            : request.refit_of
                                ? load_and_refit(request.source, *request.refit_of, on_stage, progress.get())
                                : load_and_build(request.source, request.config, on_stage, progress.get());
        request.rebuild_of.reset();  // the old scene may go now
        request.refit_of.reset();

        lock.lock();
        running_ = false;
        running_progress_.reset();
        // The newest request's result, or the error of one the user cancelled (the
        // view says so); the result of a superseded request is dropped.
        const bool wanted = cancelled_by_user_ ? !pending_.has_value() : request.id == newest_id_;
        if (wanted) {
            finished_ = std::move(result);
            activity_.clear();
            if (on_finished) on_finished();
        }
    }
}

}  // namespace accelviz

// The mesh cache: a second load of an unchanged OBJ reads its binary copy and gives
// the same mesh; a changed file, a damaged copy, a truncated copy or a copy of
// another file is never trusted (the OBJ is parsed again and the copy rewritten).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include <sys/wait.h>
#include <unistd.h>

#include "core/geometry/mesh_cache.h"
#include "core/geometry/scene.h"

namespace accelviz {
namespace {

namespace fs = std::filesystem;

/// A fresh directory under the system's temporary directory, removed afterwards.
class TempDir {
public:
    TempDir() {
        std::random_device rd;
        path_ = fs::temp_directory_path() / ("accelviz-cache-test-" + std::to_string(rd()));
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

void write_text(const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << text;
}

const char* kQuad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

bool same_mesh(const Mesh& a, const Mesh& b) {
    if (a.positions.size() != b.positions.size() || a.indices != b.indices) return false;
    for (size_t i = 0; i < a.positions.size(); ++i)
        if (!(a.positions[i] == b.positions[i])) return false;
    return a.name == b.name;
}

struct MeshCacheTest : ::testing::Test {
    TempDir dir;
    fs::path obj = dir.path() / "quad.obj";
    fs::path cache = dir.path() / "cache";

    Expected<Mesh> load(bool& from_cache) { return load_obj_cached(obj.string(), cache, &from_cache); }
    fs::path copy_file() { return mesh_cache_file(cache, *obj_key(obj.string())); }
};

TEST_F(MeshCacheTest, TheSecondLoadReadsTheCopyAndGetsTheSameMesh) {
    write_text(obj, kQuad);
    bool from_cache = true;
    const auto first = load(from_cache);
    ASSERT_TRUE(first) << first.error();
    EXPECT_FALSE(from_cache);
    EXPECT_TRUE(fs::exists(copy_file()));
    const auto second = load(from_cache);
    ASSERT_TRUE(second) << second.error();
    EXPECT_TRUE(from_cache);
    EXPECT_TRUE(same_mesh(*first, *second));
    EXPECT_EQ(second->triangle_count(), 2u);
}

TEST_F(MeshCacheTest, WritingTheCopyShowsProgressAndCanBeCancelled) {
    write_text(obj, kQuad);
    auto mesh = load_obj(obj.string());
    ASSERT_TRUE(mesh) << mesh.error();
    const ObjKey key = *obj_key(obj.string());
    // Counted to the end; its label is gone afterwards (the load's own work follows).
    WorkProgress progress;
    ASSERT_TRUE(write_mesh_cache(copy_file(), key, *mesh, &progress));
    EXPECT_EQ(progress.fraction(), 1.0);
    EXPECT_EQ(progress.stage_label(), nullptr);
    fs::remove(copy_file());
    // Cancelled: no copy and no temporary file left; a load cancelled then is cancelled.
    WorkProgress cancelled_progress;
    cancelled_progress.cancel();
    EXPECT_FALSE(write_mesh_cache(copy_file(), key, *mesh, &cancelled_progress));
    EXPECT_TRUE(fs::is_empty(cache)) << "nothing left behind";
    bool from_cache = true;
    WorkProgress cancelled_load;
    cancelled_load.cancel();
    const auto loaded = load_obj_cached(obj.string(), cache, &from_cache, &cancelled_load);
    EXPECT_FALSE(loaded);
    EXPECT_FALSE(fs::exists(copy_file()));
}

TEST_F(MeshCacheTest, TemporaryCopiesOfProcessesGoneAreRemovedWhenACopyIsWritten) {
    // A process that wrote a copy and ended without renaming or removing it (a window
    // closed mid-write): a child that exits at once gives a process id no one has.
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    ASSERT_GT(child, 0);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    fs::create_directories(cache);
    const fs::path gone = cache / ("x.mesh.tmp." + std::to_string(child));
    const fs::path alive = cache / ("y.mesh.tmp." + std::to_string(::getppid()));  // our parent runs
    const fs::path other = cache / "notes.tmp.txt";                                // not a process's copy
    for (const fs::path& p : {gone, alive, other}) write_text(p, "partial");
    write_text(obj, kQuad);
    bool from_cache = true;
    ASSERT_TRUE(load(from_cache));
    EXPECT_FALSE(from_cache);
    EXPECT_TRUE(fs::exists(copy_file()));
    EXPECT_FALSE(fs::exists(gone)) << "its process is gone";
    EXPECT_TRUE(fs::exists(alive)) << "its process runs: it may still be writing";
    EXPECT_TRUE(fs::exists(other));
}

TEST_F(MeshCacheTest, AChangedFileIsParsedAgain) {
    write_text(obj, kQuad);
    bool from_cache = false;
    ASSERT_TRUE(load(from_cache));
    // Same size, other numbers, and a modification time set back to the old one:
    // the hash of the file's ends still tells them apart.
    const auto mtime = fs::last_write_time(obj);
    write_text(obj, "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nf 1 2 3 4\n");
    fs::last_write_time(obj, mtime);
    const auto changed = load(from_cache);
    ASSERT_TRUE(changed);
    EXPECT_FALSE(from_cache);
    EXPECT_EQ(changed->positions[1].x, 2.0f);
    ASSERT_TRUE(load(from_cache));
    EXPECT_TRUE(from_cache);  // the copy was rewritten for the new version
}

TEST_F(MeshCacheTest, ADamagedOrTruncatedCopyIsNeverTrusted) {
    write_text(obj, kQuad);
    bool from_cache = false;
    const auto original = load(from_cache);
    ASSERT_TRUE(original);
    const fs::path copy = copy_file();
    const auto size = fs::file_size(copy);
    {  // one byte of the positions changed
        std::fstream f(copy, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(size - 2 * 12 - 3));
        f.put('\x7f');
    }
    auto again = load(from_cache);
    ASSERT_TRUE(again);
    EXPECT_FALSE(from_cache);
    EXPECT_TRUE(same_mesh(*original, *again));
    fs::resize_file(copy, size - 5);
    again = load(from_cache);
    ASSERT_TRUE(again);
    EXPECT_FALSE(from_cache);
    EXPECT_TRUE(same_mesh(*original, *again));
    write_text(copy, "");
    again = load(from_cache);
    ASSERT_TRUE(again);
    EXPECT_FALSE(from_cache);
    ASSERT_TRUE(load(from_cache));
    EXPECT_TRUE(from_cache);
}

TEST_F(MeshCacheTest, AnotherFilesCopyIsNotUsed) {
    write_text(obj, kQuad);
    const fs::path other = dir.path() / "other.obj";
    write_text(other, kQuad);  // same bytes, another path
    bool from_cache = false;
    ASSERT_TRUE(load(from_cache));
    // The other file's key names another copy; put this file's copy there.
    fs::copy_file(copy_file(), mesh_cache_file(cache, *obj_key(other.string())));
    const auto loaded = load_obj_cached(other.string(), cache, &from_cache);
    ASSERT_TRUE(loaded);
    EXPECT_FALSE(from_cache);
    EXPECT_EQ(loaded->name, other.string());
}

TEST_F(MeshCacheTest, BadFilesGiveTheParsersMessage) {
    bool from_cache = true;
    const auto missing = load(from_cache);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().find("no such file"), std::string::npos) << missing.error();
    write_text(obj, "v 0 0 0\nf 1 2 3\n");
    const auto bad = load(from_cache);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error(), load_obj(obj.string()).error());
    EXPECT_FALSE(fs::exists(cache) && !fs::is_empty(cache));  // nothing is cached for a file that fails
}

}  // namespace
}  // namespace accelviz

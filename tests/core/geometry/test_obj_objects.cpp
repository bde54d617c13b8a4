// An OBJ file's objects (the faces between o / g statements) and builtin:mirror,
// which makes one of them a mirror: the triangles flagged are exactly that object's,
// in load_obj's numbering (polygons fanned), and the ray caster reflects off them.
#include <algorithm>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/camera.h"
#include "core/render/lighting.h"
#include "core/render/ray_caster.h"

using namespace accelviz;

namespace {

std::string write_obj(const std::string& name, const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() / ("accelviz_" + name);
    std::ofstream(path) << text;
    return path.string();
}

// Faces before any statement (object 0: one triangle), "o floor" with a triangle and a
// quad (3 triangles), two statements with nothing between ("g a", "g mirror": one
// object, named by the last) holding a pentagon (3 triangles), a comment and blanks.
const char* kRoom =
    "v 0 0 0\nv 4 0 0\nv 4 0 4\nv 0 0 4\nv 2 3 2\n"
    "f 1 2 5\n"
    "o floor\n"
    "f 1 2 3\n"
    "f 1 3 4 2 # a quad\n"
    "g a\n"
    "  g   mirror  \n"
    "f 1 2 3 4 5\n";

}  // namespace

TEST(ObjObjects, RunsOfFacesBetweenStatementsInLoadObjsNumbering) {
    const std::string path = write_obj("room.obj", kRoom);
    auto objects = obj_objects(path);
    ASSERT_TRUE(objects) << objects.error();
    ASSERT_EQ(objects->size(), 3u);
    EXPECT_EQ((*objects)[0].name, "");
    EXPECT_EQ((*objects)[0].first_triangle, 0u);
    EXPECT_EQ((*objects)[0].triangle_count, 1u);
    EXPECT_EQ((*objects)[1].name, "floor");
    EXPECT_EQ((*objects)[1].first_triangle, 1u);
    EXPECT_EQ((*objects)[1].triangle_count, 3u);
    EXPECT_EQ((*objects)[2].name, "mirror");
    EXPECT_EQ((*objects)[2].first_triangle, 4u);
    EXPECT_EQ((*objects)[2].triangle_count, 3u);
    auto mesh = load_obj(path);
    ASSERT_TRUE(mesh) << mesh.error();
    EXPECT_EQ(mesh->triangle_count(), 7u) << "the objects cover every triangle load_obj makes";
}

TEST(ObjObjects, BuiltinMirrorFlagsExactlyThatObjectAndTheRayCasterReflectsOffIt) {
    const std::string path = write_obj("room2.obj", kRoom);
    auto mesh = load_scene("builtin:mirror?mesh=" + path + "&object=1");
    ASSERT_TRUE(mesh) << mesh.error();
    ASSERT_EQ(mesh->mirror.size(), 7u);
    for (size_t tri = 0; tri < 7; ++tri) EXPECT_EQ(mesh->mirror[tri], tri >= 1 && tri < 4 ? 1 : 0) << tri;

    auto missing = load_scene("builtin:mirror?mesh=" + path + "&object=3");
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().find("has 3 objects (0 (unnamed), 1 floor, 2 mirror)"), std::string::npos)
        << missing.error();
    auto whole = load_scene("builtin:mirror?mesh=builtin:sphere&object=0");  // a built-in: one object
    ASSERT_TRUE(whole) << whole.error();
    EXPECT_EQ(std::count(whole->mirror.begin(), whole->mirror.end(), 1), std::ptrdiff_t(whole->triangle_count()));
    EXPECT_FALSE(load_scene("builtin:mirror?mesh=builtin:sphere&object=1"));

    // Looking down at the floor (the mirror): reflection rays leave it.
    AccelConfig config;
    config.type = AccelType::Bvh;
    auto accel = build_accelerator(*mesh, config);
    ASSERT_TRUE(accel);
    CameraParams params;
    params.eye = {2, 6, 2.5};
    params.target = {2, 0, 2};
    const Camera camera(params, 64, 48);
    Lighting lighting;
    lighting.light = {2, 2.5, 1};
    lighting.reflections = true;
    lighting.mirror = mesh->mirror;
    const Frame frame = ray_cast(**accel, *mesh, camera, {.threads = 1, .count_work = true, .lighting = &lighting});
    size_t on_mirror = 0;
    for (uint32_t tri : frame.tri) on_mirror += tri != Hit::kNoHit && mesh->mirror[tri] ? 1 : 0;
    EXPECT_GT(on_mirror, 100u) << "the camera sees the floor";
    EXPECT_EQ(frame.reflection.rays, on_mirror) << "one reflection ray from every mirror pixel";
}

TEST(ObjObjects, AByteOrderMarkAndAnObjectWithoutFaces) {
    // The loader skips a UTF-8 byte-order mark, so the objects must too; a statement at
    // the end names an object with no faces, which cannot be a mirror.
    const std::string path = write_obj("bom.obj", "\xEF\xBB\xBFo first\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ng last\n");
    auto objects = obj_objects(path);
    ASSERT_TRUE(objects) << objects.error();
    ASSERT_EQ(objects->size(), 2u);
    EXPECT_EQ((*objects)[0].name, "first");
    EXPECT_EQ((*objects)[0].triangle_count, 1u);
    EXPECT_EQ((*objects)[1].triangle_count, 0u);
    auto empty = load_scene("builtin:mirror?mesh=" + path + "&object=1");
    ASSERT_FALSE(empty);
    EXPECT_NE(empty.error().find("has no faces"), std::string::npos) << empty.error();
}

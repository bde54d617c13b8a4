// A structure from a file (a student's tree) in the window: dropped on it or typed
// into the Structure panel, read and checked on the worker; a valid one is drawn
// and traced like ours, an invalid one drawn with the nodes its problems name in red.
#include <cstdio>

#include <gtest/gtest.h>

#include "app/gui/headless.h"
#include "app/gui/session.h"
#include "core/exchange/file_tree_order.h"
#include "core/accel/factory.h"
#include "core/exchange/structure_file.h"
#include "core/geometry/scene.h"
#include "golden.h"

namespace accelviz {
namespace {

using testing::draw_until_loaded;

/// A headless window session (width x height) with `state`'s scene and structure loaded.
std::unique_ptr<HeadlessApp> session_with(AppState& state, int width, int height) {
    auto app = HeadlessApp::create(width, height);
    EXPECT_TRUE(app) << app.error();
    if (!app) return nullptr;
    (*app)->session().open_scene(state, state.scene);
    draw_until_loaded(**app, state);
    return std::move(*app);
}

const std::string kBrokenTree = std::string(ACCELVIZ_TREES_DIR) + "/teapot_student_broken.json";


/// Our median BVH of builtin:teapot written to a file, as a student's tool would.
std::string write_our_tree(const char* name) {
    const Mesh mesh = *load_scene("builtin:teapot", MeshCache::Skip);
    AccelConfig c;
    c.type = AccelType::Bvh;
    c.bvh.builder = BvhBuilder::Median;
    auto accel = build_accelerator(mesh, c);
    auto file = export_structure(**accel, mesh, {"builtin:teapot", 0, *mesh_crc32("builtin:teapot", mesh)});
    const std::string path = ::testing::TempDir() + name;
    EXPECT_FALSE(write_structure_file(*file, path).has_value());
    return path;
}

TEST(StructureFileView, ADroppedValidTreeIsDrawnAndTracedLikeOurs) {
    AppState state;
    state.scene = "builtin:teapot";
    state.accel.bvh.builder = BvhBuilder::Median;
    auto app = session_with(state, 480, 320);
    ASSERT_TRUE(app);
    const size_t our_boxes = app->session().overlay.boxes.size();
    ASSERT_GT(our_boxes, 0u);

    const std::string tree = write_our_tree("valid_tree.json");
    FrameInput drop;
    drop.dropped_paths = {tree};
    app->draw(state, drop);
    draw_until_loaded(*app, state);
    const Session& session = app->session();
    ASSERT_NE(session.scene, nullptr);
    EXPECT_EQ(state.scene, "builtin:teapot") << "a tree is not a scene: the mesh stays";
    EXPECT_EQ(state.accel.structure_file, tree);
    ASSERT_NE(session.scene->structure_file, nullptr) << session.message;
    EXPECT_TRUE(session.scene->structure_file->check.valid());
    EXPECT_EQ(session.scene->accel->name(), "bvh") << "our traversal, through the file's tree";
    EXPECT_EQ(session.overlay.boxes.size(), our_boxes) << "the same tree, the same boxes";
    EXPECT_EQ(session.overlay.legend.find("NOT VALID"), std::string::npos);
    // Traced through the file's tree: the closest hits of brute force, with work counted.
    AccelConfig naive;
    naive.type = AccelType::Naive;
    const auto brute = *build_accelerator(*session.scene->mesh, naive);
    const Camera camera(*state.camera, 48, 32);
    uint64_t hits = 0, nodes = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 48; ++x) {
            const Ray ray = camera.ray(x, y);
            CountingObserver counter;
            const Hit got = session.scene->accel->intersect_closest(ray, counter);
            const Hit want = brute->intersect_closest(ray);
            ASSERT_EQ(got.tri, want.tri) << x << "," << y;
            ASSERT_EQ(got.t, want.t);
            hits += got.found();
            nodes += counter.counters.nodes_visited;
        }
    EXPECT_GT(hits, 100u);
    EXPECT_GT(nodes, 48u * 32u);
}

TEST(StructureFileView, AnInvalidTreeIsDrawnWithItsFaultyNodesRed) {
    AppState state;
    state.scene = "builtin:teapot";
    state.accel.structure_file = kBrokenTree;
    auto app = session_with(state, 480, 320);
    ASSERT_TRUE(app);
    const Session& session = app->session();
    ASSERT_NE(session.scene, nullptr) << session.message;
    ASSERT_NE(session.scene->structure_file, nullptr);
    const StructureCheck& check = session.scene->structure_file->check;
    EXPECT_FALSE(check.valid());
    EXPECT_EQ(check.bad_nodes, (std::vector<uint64_t>{130, 193, 194})) << "the children sticking out and their parent";
    EXPECT_EQ(session.scene->accel->name(), "naive") << "rays go through brute force: they get the right answers";
    size_t red = 0;
    for (const BoxInstance& b : session.overlay.boxes) red += b.colour.r == 255 && b.colour.g == 40 && b.colour.a == 255;
    EXPECT_EQ(red, 3u);
    EXPECT_NE(session.overlay.legend.find("NOT VALID: 2 problems"), std::string::npos) << session.overlay.legend;
}

TEST(StructureFileView, AnInvalidTreeIsRayCastOnlyWhenAsked) {
    // Its rays go through brute force: auto rasterizes even when rasterizing is slow;
    // Draw with: ray cast casts it.
    AppState state;
    state.scene = "builtin:teapot";
    state.accel.structure_file = kBrokenTree;
    state.view.draw_with = DrawWith::Auto;
    auto app = session_with(state, 320, 240);
    ASSERT_TRUE(app);
    Session& session = app->session();
    ASSERT_NE(session.scene, nullptr) << session.message;
    session.raster_ms_per_triangle = 1.0;
    FrameInput input;
    input.draw_ui = false;
    app->draw(state, input);
    EXPECT_FALSE(session.mesh_ray_cast);
    state.view.draw_with = DrawWith::RayCast;
    app->draw(state, input);
    EXPECT_TRUE(session.mesh_ray_cast);
    EXPECT_FALSE(session.brute_force_cast_refused) << "3,552 triangles x 76,800 pixels is within the budget";
}

TEST(StructureFileView, AnUnreadableTreeIsAMessageAndTheStructureStays) {
    AppState state;
    state.scene = "builtin:cube";
    auto app = session_with(state, 320, 240);
    ASSERT_TRUE(app);
    const auto before = app->session().scene;
    const std::string bad = ::testing::TempDir() + "not_a_tree.json";
    std::FILE* f = std::fopen(bad.c_str(), "w");
    std::fputs("{\"format\": \"accelviz-structure\", \"version\": 1, \"type\": \"bvh\"}", f);
    std::fclose(f);
    app->session().use_structure_file(state, bad);
    draw_until_loaded(*app, state);
    EXPECT_EQ(app->session().scene, before);
    EXPECT_NE(app->session().message.find("\"mesh\" is missing"), std::string::npos) << app->session().message;
}

TEST(StructureFileView, StudentTreeWithAnInvalidNodeMatchesGolden) {
    AppState state;
    state.scene = "builtin:teapot";
    state.accel.structure_file = kBrokenTree;
    EXPECT_TRUE(testing::view_matches_golden(state, WindowView::Gui, 960, 600, "teapot_student_tree_invalid"));
}

TEST(StructureFileView, TheConstructionStepperStepsTheFilesNodesInItsOrder) {
    // Stepping our builder's recording here would show another tree than the one drawn:
    // the stepper steps the file's own nodes, numbered as the file numbers them.
    auto app = HeadlessApp::create(480, 320);
    ASSERT_TRUE(app) << app.error();
    AppState state;
    state.scene = "builtin:teapot";
    state.build_step.active = true;
    state.build_step.step = 2;
    state.accel.structure_file = write_our_tree("stepped_tree.json");
    (*app)->session().open_scene(state, state.scene);
    testing::draw_until_loaded(**app, state);
    for (int i = 0; i < 3; ++i) (*app)->draw(state, {});
    const Session& session = (*app)->session();
    ASSERT_NE(session.scene, nullptr) << session.message;
    ASSERT_NE(session.scene->structure_file, nullptr);
    EXPECT_EQ(session.build_stepper.trace(), nullptr) << "no recording of our build";
    ASSERT_NE(session.build_stepper.file_trace(), nullptr);
    const FileNodeStep* node = session.build_stepper.file_node();
    ASSERT_NE(node, nullptr);
    EXPECT_EQ(node->node, 2u);
    EXPECT_TRUE(session.build_stepper.shows_3d(state));
    // The node shown is the file's node 2: its box and its children's.
    const StructureFile& file = *session.scene->structure_file->file;
    EXPECT_EQ(node->box, file.bvh_nodes[2].box);
    ASSERT_EQ(node->children.size(), file.bvh_nodes[2].children.size());
    for (size_t k = 0; k < node->children.size(); ++k) EXPECT_EQ(node->children[k], file.bvh_nodes[2].children[k]);
    // Past the end: the last node (the stepper clamps, as over our build).
    state.build_step.step = 1 << 20;
    for (int i = 0; i < 3; ++i) (*app)->draw(state, {});
    EXPECT_EQ(state.build_step.step, int(file.bvh_nodes.size()) - 1);
    ASSERT_NE(session.build_stepper.file_node(), nullptr);
    EXPECT_EQ(session.build_stepper.file_node()->node, file.bvh_nodes.size() - 1);
}

TEST(StructureFileView, AFaultyNodeOfAStudentTreeSteppedMatchesGolden) {
    // Node 130 of the broken tree: its children's boxes stick out of its box (red).
    AppState state;
    state.scene = "builtin:teapot";
    state.accel.structure_file = kBrokenTree;
    state.build_step.active = true;
    state.build_step.step = 130;
    EXPECT_TRUE(testing::view_matches_golden(state, WindowView::BuildStep, 960, 600, "teapot_student_tree_node130"));
}

}  // namespace
}  // namespace accelviz

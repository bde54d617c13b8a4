// The exchange format: our structures go out and come back as the same trees, the
// same closest hits as brute force through them; a hand-made broken tree is caught
// with the node it is about; malformed files are clear errors.
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "accel/accel_test_support.h"
#include "core/accel/factory.h"
#include "core/exchange/structure_check.h"
#include "core/exchange/structure_file.h"
#include "core/geometry/scene.h"
#include "core/util/crc32.h"

namespace accelviz {
namespace {

Mesh scene(const std::string& source) {
    auto mesh = load_scene(source, MeshCache::Skip);
    EXPECT_TRUE(mesh.ok()) << source;
    return std::move(*mesh);
}

std::shared_ptr<const Accelerator> build(const Mesh& mesh, AccelType type, int width = 2) {
    AccelConfig c;
    c.type = type;
    c.bvh.width = width;
    auto accel = build_accelerator(mesh, c);
    EXPECT_TRUE(accel.ok()) << accel.error();
    return *accel;
}

std::vector<std::string> messages(const StructureCheck& check) {
    std::vector<std::string> out;
    for (const auto& p : check.problems) out.push_back(p.message);
    return out;
}

std::string joined(const StructureCheck& check) {
    std::string s;
    for (const auto& m : messages(check)) s += m + "\n";
    return s;
}

/// The file's tree in a form that ignores node numbering: every node as its box and
/// either its children's forms or its triangle list, from the root down.
std::string canonical(const StructureFile& f) {
    std::function<std::string(uint32_t)> bvh = [&](uint32_t i) {
        const FileBvhNode& n = f.bvh_nodes[i];
        std::string s = "(" + std::to_string(n.box.lo.x) + "," + std::to_string(n.box.hi.y) + "," +
                        std::to_string(n.box.area());
        if (n.interior) {
            for (uint32_t c : n.children) s += bvh(c);
        } else {
            for (uint64_t k = n.first; k < n.first + n.count; ++k) s += " " + std::to_string(f.order[k]);
        }
        return s + ")";
    };
    std::function<std::string(uint32_t)> kd = [&](uint32_t i) {
        const FileKdNode& n = f.kd_nodes[i];
        if (n.is_leaf()) {
            std::string s = "[";
            for (uint32_t t : n.triangles) s += " " + std::to_string(t);
            return s + "]";
        }
        return "(" + std::to_string(n.axis) + ":" + std::to_string(n.split) + kd(n.children[0]) + kd(n.children[1]) +
               ")";
    };
    if (f.type == AccelType::Bvh) return f.bvh_nodes.empty() ? "" : bvh(0);
    if (f.type == AccelType::Kd) return f.kd_nodes.empty() ? "" : kd(0);
    return structure_json(f);
}

TEST(Crc32, MatchesZlibsCheckValue) {
    Crc32 crc;
    crc.add("123456789", 9);
    EXPECT_EQ(crc.value(), 0xCBF43926u);
}

// Export, write, read, check, load: the same tree, valid, and exact through our walk.
TEST(StructureFile, OurStructuresComeBackAsTheSameTreesAndExact) {
    for (const std::string source : {"builtin:teapot", "builtin:same-centroid", "builtin:single"}) {
        const Mesh mesh = scene(source);
        const std::vector<Ray> rays = test::make_test_rays(mesh, 3000, 7);
        const std::vector<Hit> want = test::brute_force_answers(mesh, rays);
        const auto crc = mesh_crc32(source, mesh);
        ASSERT_TRUE(crc.ok());
        struct Kind {
            AccelType type;
            int width;
        };
        for (const Kind kind : {Kind{AccelType::Bvh, 2}, Kind{AccelType::Bvh, 4}, Kind{AccelType::Bvh, 8},
                                Kind{AccelType::Kd, 2}, Kind{AccelType::Grid, 2}}) {
            SCOPED_TRACE(source + " " + std::string(to_string(kind.type)) + " width " + std::to_string(kind.width));
            const auto ours = build(mesh, kind.type, kind.width);
            auto exported = export_structure(*ours, mesh, {source, 0, *crc});
            ASSERT_TRUE(exported.ok()) << exported.error();
            for (const bool binary : {false, true}) {
                auto read = binary ? parse_structure_binary(structure_binary(*exported))
                                   : parse_structure_json(structure_json(*exported));
                ASSERT_TRUE(read.ok()) << read.error();
                EXPECT_EQ(structure_json(*read), structure_json(*exported));
                const StructureCheck check = check_structure(*read, mesh, *crc);
                EXPECT_TRUE(check.valid()) << joined(check);
                auto loaded = structure_accelerator(*read, mesh);
                ASSERT_TRUE(loaded.ok()) << loaded.error();
                // Loaded and exported again: the same tree (node numbers may differ).
                auto again = export_structure(**loaded, mesh, {source, 0, *crc});
                ASSERT_TRUE(again.ok());
                EXPECT_EQ(canonical(*again), canonical(*exported));
                for (size_t r = 0; r < rays.size(); ++r)
                    ASSERT_TRUE(test::same_hit((*loaded)->intersect_closest(rays[r]), want[r]))
                        << test::describe(rays[r]);
            }
        }
    }
}

TEST(StructureFile, TheFiguresOfOurTreeLoadedEqualOursBuilt) {
    const Mesh mesh = scene("builtin:teapot");
    const auto ours = build(mesh, AccelType::Bvh, 4);
    auto file = export_structure(*ours, mesh, {"builtin:teapot", 0, std::nullopt});
    ASSERT_TRUE(file.ok());
    auto loaded = structure_accelerator(*file, mesh);
    ASSERT_TRUE(loaded.ok());
    const std::vector<Ray> rays = test::make_test_rays(mesh, 2000, 3);
    const StructureFigures a = measure_structure(*file, mesh, **loaded, rays, *ours, {});
    const StructureFigures b = measure_structure(*file, mesh, *ours, rays, *ours, {});
    EXPECT_EQ(a.mismatches, 0u);
    EXPECT_EQ(a.nodes_per_ray, b.nodes_per_ray);
    EXPECT_EQ(a.box_tests_per_ray, b.box_tests_per_ray);
    EXPECT_EQ(a.triangle_tests_per_ray, b.triangle_tests_per_ray);
    EXPECT_GT(a.avg_children, 2.0);
    EXPECT_LE(a.avg_children, 4.0);
    EXPECT_EQ(a.references, 1.0);
    uint64_t leaves = 0;
    for (uint64_t k : a.leaf_sizes) leaves += k;
    EXPECT_EQ(leaves, a.leaves);
}

// [SECTION] Hand-made trees over four triangles in a row along x.

Mesh four_in_a_row() {
    Mesh m;
    for (int i = 0; i < 4; ++i) {
        const auto base = uint32_t(m.positions.size());
        m.positions.push_back({float(i), 0, 0});
        m.positions.push_back({float(i) + 0.8f, 0, 0});
        m.positions.push_back({float(i), 1, 0});
        m.indices.push_back({base, base + 1, base + 2});
    }
    return m;
}

Aabb box(float x0, float x1) { return {{x0, 0, 0}, {x1, 1, 0}}; }

/// Root over all, two leaves of two triangles each.
StructureFile good_bvh() {
    StructureFile f;
    f.type = AccelType::Bvh;
    f.mesh.triangles = 4;
    f.order = {0, 1, 2, 3};
    f.bvh_nodes = {{box(0, 3.8f), true, {1, 2}, 0, 0}, {box(0, 1.8f), false, {}, 0, 2}, {box(2, 3.8f), false, {}, 2, 2}};
    return f;
}

/// Split at x = 2 into two leaf cells.
StructureFile good_kd() {
    StructureFile f;
    f.type = AccelType::Kd;
    f.mesh.triangles = 4;
    f.bounds = {{-0.1f, -0.5f, -0.5f}, {3.9f, 1.5f, 0.5f}};  // a margin, as our trees have
    FileKdNode root;
    root.axis = 0;
    root.split = 1.9f;
    root.children = {1, 2};
    FileKdNode lower, upper;
    lower.triangles = {0, 1};
    upper.triangles = {2, 3};
    f.kd_nodes = {root, lower, upper};
    return f;
}

/// Four cells along x, one triangle each (a triangle touching a cell must be listed
/// there too: these don't touch their neighbours).
StructureFile good_grid() {
    StructureFile f;
    f.type = AccelType::Grid;
    f.mesh.triangles = 4;
    f.bounds = {{-0.1f, -0.5f, -0.5f}, {3.9f, 1.5f, 0.5f}};  // planes at 0.9, 1.9, 2.9: no triangle touches one
    f.resolution = {4, 1, 1};
    for (uint32_t i = 0; i < 4; ++i) f.cells.push_back({{i, 0, 0}, {i}});
    return f;
}

/// Whether `check` names node `node` with a message containing `words`.
::testing::AssertionResult names(const StructureCheck& check, std::optional<uint64_t> node, const std::string& words) {
    if (check.valid()) return ::testing::AssertionFailure() << "the tree passed";
    for (const auto& p : check.problems)
        if (p.node == node && p.message.find(words) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "no problem on that node with \"" << words << "\" among:\n" << joined(check);
}

TEST(StructureCheck, TheGoodHandMadeTreesAreValid) {
    const Mesh mesh = four_in_a_row();
    for (const StructureFile& f : {good_bvh(), good_kd(), good_grid()}) {
        const StructureCheck check = check_structure(f, mesh, std::nullopt);
        EXPECT_TRUE(check.valid()) << joined(check);
        auto accel = structure_accelerator(f, mesh);
        ASSERT_TRUE(accel.ok());
        const std::vector<Ray> rays = test::make_test_rays(mesh, 500, 11);
        const std::vector<Hit> want = test::brute_force_answers(mesh, rays);
        for (size_t r = 0; r < rays.size(); ++r)
            EXPECT_EQ((*accel)->intersect_closest(rays[r]).tri, want[r].tri) << test::describe(rays[r]);
    }
}

TEST(StructureCheck, CatchesEachBvhFaultWithItsNode) {
    const Mesh mesh = four_in_a_row();
    auto with = [&](const std::function<void(StructureFile&)>& edit) {
        StructureFile f = good_bvh();
        edit(f);
        return check_structure(f, mesh, std::nullopt);
    };
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[1].box.hi.y = 1.5f; }), 1, "sticks out of its parent's (node 0) by 0.5 on +y"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[2].box.lo.x = 2.5f; }), 2, "triangle 2 sticks out of its leaf's box (node 2) by 0.5 on -x"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[2].count = 1; }), std::nullopt, "1 triangle is in no leaf (3)"));
    EXPECT_TRUE(names(with([](auto& f) { f.order[3] = 1; }), 1, "triangle 1 is in 2 leaves"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[2] = {box(0, 3.8f), true, {0}, 0, 0}; }), 2, "cycle"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[0].children = {1, 1}; }), 0, "node 1 is reached a second time, from node 0"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[2].first = 1; }), 2, "overlaps another leaf's (at 1)"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes.push_back({box(0, 1), false, {}, 0, 1}); }), 3, "not reachable"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[2] = {box(2, 3.8f), true, {}, 0, 0}; }), 2, "empty inner node"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[0].children = {1}; }), 0, "one child"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[0].children = {1, 2, 1, 2, 1, 2, 1, 2, 1}; }), 0, "9 children"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[0].children = {1, 7}; }), 0, "names child 7"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[2].count = 3; }), 2, "run past the end of \"order\""));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[1].count = 0; }), 1, "leaf with no triangles"));
    EXPECT_TRUE(names(with([](auto& f) { f.order[0] = 9; }), 1, "not a triangle"));
    EXPECT_TRUE(names(with([](auto& f) { f.bvh_nodes[1].box.lo.y = 2; }), 1, "is not a box"));
    EXPECT_TRUE(names(with([](auto& f) { f.mesh.triangles = 5; }), std::nullopt, "a mesh of 5 triangles"));
    StructureFile other = good_bvh();
    other.mesh.crc32 = 0x1234;
    EXPECT_TRUE(names(check_structure(other, mesh, 0x5678), std::nullopt, "CRC-32 00001234"));
    // A chain 70 levels deep: each interior node a leaf and the next interior node.
    StructureFile deep = good_bvh();
    deep.bvh_nodes.clear();
    for (uint32_t level = 0; level < 70; ++level) {
        const auto me = uint32_t(deep.bvh_nodes.size());
        deep.bvh_nodes.push_back({box(0, 3.8f), true, {me + 1, me + 2}, 0, 0});
        deep.bvh_nodes.push_back({box(0, 3.8f), false, {}, 0, 4});
    }
    deep.bvh_nodes.push_back({box(0, 3.8f), false, {}, 0, 4});
    EXPECT_TRUE(names(check_structure(deep, mesh, std::nullopt), std::nullopt, "70 levels deep"));
}

TEST(StructureCheck, CatchesKdAndGridFaults) {
    const Mesh mesh = four_in_a_row();
    StructureFile kd = good_kd();
    kd.kd_nodes[1].triangles = {0};  // triangle 1 (x 1 to 1.8) lies in the lower cell
    EXPECT_TRUE(names(check_structure(kd, mesh, std::nullopt), 1, "triangle 1 overlaps leaf node 1's cell"));
    kd = good_kd();
    kd.kd_nodes[0].split = 7;
    EXPECT_TRUE(names(check_structure(kd, mesh, std::nullopt), 0, "not inside its cell"));
    kd = good_kd();
    kd.kd_nodes[2].triangles = {2, 3, 1};  // an extra triangle is wasteful, not wrong
    EXPECT_TRUE(check_structure(kd, mesh, std::nullopt).valid());
    kd.bounds.hi.x = 3;
    EXPECT_TRUE(names(check_structure(kd, mesh, std::nullopt), std::nullopt, "sticks out of \"bounds\" by 0.8 on +x"));

    StructureFile grid = good_grid();
    grid.cells[2].triangles = {};
    EXPECT_TRUE(names(check_structure(grid, mesh, std::nullopt), 2, "triangle 2 overlaps cell (2, 0, 0)"));
    grid = good_grid();
    grid.cells.pop_back();
    EXPECT_TRUE(names(check_structure(grid, mesh, std::nullopt), std::nullopt, "triangle 3 overlaps cell (3, 0, 0)"));
    grid = good_grid();
    grid.cells[0].cell = {4, 0, 0};
    EXPECT_TRUE(names(check_structure(grid, mesh, std::nullopt), 0, "outside the grid"));
    grid = good_grid();
    grid.resolution = {0, 1, 1};
    EXPECT_TRUE(names(check_structure(grid, mesh, std::nullopt), std::nullopt, "\"resolution\""));
    grid.resolution = {4194304, 2097152, 2097152};  // 2^64 cells: a product that would wrap to 0
    EXPECT_TRUE(names(check_structure(grid, mesh, std::nullopt), std::nullopt, "\"resolution\""));
}

TEST(StructureFile, MalformedFilesAreClearErrors) {
    auto error = [](const std::string& text) {
        auto f = parse_structure_json(text);
        return f.ok() ? std::string("(parsed)") : f.error();
    };
    const std::string head = R"({"format":"accelviz-structure","version":1,"type":"bvh","mesh":{"triangles":4},)";
    EXPECT_NE(error("{nope").find("not JSON"), std::string::npos);
    EXPECT_NE(error(R"({"format": 1e999})").find("not JSON"), std::string::npos);  // out_of_range, not parse_error
    EXPECT_NE(error(R"({"format":"x"})").find("\"format\""), std::string::npos);
    EXPECT_NE(error(R"({"format":"accelviz-structure","version":2})").find("reads version 1"), std::string::npos);
    EXPECT_NE(error(head + R"("order":[0],"nodes":[{"box":[0,0,0,1,1]}]})").find("node 0: \"box\" must be 6 numbers"),
              std::string::npos);
    EXPECT_NE(error(head + R"("order":[-1],"nodes":[]})").find("\"order\" must be a whole number"), std::string::npos);
    EXPECT_NE(error(head + R"("order":[0],"nodes":[{"box":[0,0,0,1,1,1],"first":0}]})").find("node 0: \"count\" is missing"),
              std::string::npos);
    EXPECT_NE(error(head + R"("order":[0],"nodes":[{"box":[0,0,0,1,1,1],"children":[1],"first":0,"count":1}]})")
                  .find("interior or a leaf, not both"),
              std::string::npos);
    EXPECT_EQ(error(head + R"("order":[0],"nodes":[{"box":[0,0,0,1,1,1],"first":0,"count":1}]})"), "(parsed)");

    // The binary variant: every truncation is an error, never a crash or a huge allocation.
    const Mesh mesh = four_in_a_row();
    const std::string bytes = structure_binary(good_bvh());
    for (size_t n = 0; n < bytes.size(); ++n) EXPECT_FALSE(parse_structure_binary(bytes.substr(0, n)).ok()) << n;
    EXPECT_FALSE(parse_structure_binary(bytes + "x").ok());
    EXPECT_TRUE(parse_structure_binary(bytes).ok());
    // A leaf's first near 2^64 (binary fields are 64 bits; first + count would wrap).
    StructureFile wraps = good_bvh();
    wraps.bvh_nodes[2].first = ~uint64_t(0);
    wraps.bvh_nodes[2].count = 1;
    EXPECT_FALSE(parse_structure_binary(structure_binary(wraps)).ok());
    wraps.bvh_nodes[2].first = UINT32_MAX;  // in range for the parser: check refuses it without wrapping
    auto read = parse_structure_binary(structure_binary(wraps));
    ASSERT_TRUE(read.ok());
    EXPECT_TRUE(names(check_structure(*read, mesh, std::nullopt), 2, "run past the end"));
}

}  // namespace
}  // namespace accelviz

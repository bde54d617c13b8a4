// load_obj: small OBJ files written by the test (good and malformed, each error
// naming the file and the line), and the real meshes of ../shared/assets.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/geometry/scene.h"
#include "test_support.h"

using namespace accelviz;

namespace {

/// Each test gets its own scratch directory, removed afterwards.
class ObjFiles : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = std::filesystem::temp_directory_path() /
               ("accelviz_obj_" + std::to_string(::getpid()) + "_" + info->name());
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    /// Writes `text` byte for byte to DIR/name and returns the path.
    std::string write(const std::string& name, const std::string& text) {
        const std::string path = (dir_ / name).string();
        std::ofstream(path, std::ios::binary) << text;
        return path;
    }
    std::filesystem::path dir_;
};

void expect_contains(const std::string& text, const std::string& part) {
    EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' not in: " << text;
}

using Tri = std::array<uint32_t, 3>;

}  // namespace

// ---------------------------------------------------------------------------
// Good files
// ---------------------------------------------------------------------------

TEST_F(ObjFiles, TrianglesKeepTheirPositionsAndIndices) {
    const std::string path = write("two.obj",
                                   "# two triangles\n"
                                   "v 0 0 0\n"
                                   "v 1.5 0 0\n"
                                   "v 0 -2.25 0\n"
                                   "v 0 0 3e2\n"
                                   "f 1 2 3\n"
                                   "f 1 3 4\n");
    auto mesh = load_obj(path);
    ASSERT_TRUE(mesh.ok()) << mesh.error();
    EXPECT_EQ(mesh->name, path);
    ASSERT_EQ(mesh->triangle_count(), 2u);
    ASSERT_EQ(mesh->positions.size(), 4u);
    EXPECT_EQ(mesh->positions[1], (Vec3{1.5f, 0, 0}));
    EXPECT_EQ(mesh->positions[2], (Vec3{0, -2.25f, 0}));
    EXPECT_EQ(mesh->positions[3], (Vec3{0, 0, 300}));
    EXPECT_EQ(mesh->indices[0], (Tri{0, 1, 2}));
    EXPECT_EQ(mesh->indices[1], (Tri{0, 2, 3}));
}

TEST_F(ObjFiles, QuadAndPentagonAreFanTriangulated) {
    const std::string path = write("polygons.obj",
                                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"              // a unit square
                                   "v 0 0 1\nv 2 0 1\nv 3 1 1\nv 1 2 1\nv -1 1 1\n"  // a pentagon
                                   "f 1 2 3 4\n"
                                   "f 5 6 7 8 9\n");
    auto mesh = load_obj(path);
    ASSERT_TRUE(mesh.ok()) << mesh.error();
    ASSERT_EQ(mesh->triangle_count(), 2u + 3u);
    // A fan from the first corner, in the polygon's order.
    EXPECT_EQ(mesh->indices[0], (Tri{0, 1, 2}));
    EXPECT_EQ(mesh->indices[1], (Tri{0, 2, 3}));
    EXPECT_EQ(mesh->indices[2], (Tri{4, 5, 6}));
    EXPECT_EQ(mesh->indices[3], (Tri{4, 6, 7}));
    EXPECT_EQ(mesh->indices[4], (Tri{4, 7, 8}));
}

TEST_F(ObjFiles, NegativeIndicesCountBackFromTheLatestVertex) {
    const std::string path = write("relative.obj",
                                   "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                   "f -3 -2 -1\n"
                                   "v 5 0 0\nv 6 0 0\nv 5 1 0\n"
                                   "f -3 -2 -1\n"
                                   "f 1 -2 -1\n");  // absolute and relative mixed
    auto mesh = load_obj(path);
    ASSERT_TRUE(mesh.ok()) << mesh.error();
    ASSERT_EQ(mesh->triangle_count(), 3u);
    EXPECT_EQ(mesh->indices[0], (Tri{0, 1, 2}));
    EXPECT_EQ(mesh->indices[1], (Tri{3, 4, 5}));
    EXPECT_EQ(mesh->indices[2], (Tri{0, 4, 5}));
    EXPECT_EQ(mesh->vertex(1, 0), (Vec3{5, 0, 0}));
}

TEST_F(ObjFiles, TextureNormalIndicesGroupsAndMaterialsAreIgnored) {
    const std::string path = write("full.obj",
                                   "mtllib does_not_exist.mtl\n"
                                   "o thing\n"
                                   "g part\n"
                                   "usemtl red\n"
                                   "s 1\n"
                                   "  v 0 0 0   # origin\n"  // leading blanks, a comment at the end
                                   "v\t1 0 0 1.0\n"  // tab, and the optional w
                                   "v 0 1 0 0.5 0.5 0.5\n"  // a vertex colour
                                   "vt 0 0\nvn 0 0 1\n"
                                   "f 1/1/1 2/1/1 3/1/1\n"
                                   "g other\n"
                                   "f 1//1 2//1 3//1 # a comment\n"
                                   "f 1/1 2/1 3/1\n"
                                   "l 1 2\n");
    auto mesh = load_obj(path);
    ASSERT_TRUE(mesh.ok()) << mesh.error();
    ASSERT_EQ(mesh->triangle_count(), 3u);
    for (size_t t = 0; t < 3; ++t) EXPECT_EQ(mesh->indices[t], (Tri{0, 1, 2}));
    EXPECT_EQ(mesh->positions[1], (Vec3{1, 0, 0}));
}

TEST_F(ObjFiles, IndicesMayPointForwardToLaterVertices) {
    auto mesh = load_obj(write("forward.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"));
    ASSERT_TRUE(mesh.ok()) << mesh.error();
    EXPECT_EQ(mesh->triangle_count(), 1u);
}

TEST_F(ObjFiles, WindowsAndOldMacLineEndings) {
    auto crlf = load_obj(write("crlf.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n"));
    ASSERT_TRUE(crlf.ok()) << crlf.error();
    EXPECT_EQ(crlf->triangle_count(), 1u);
    auto cr = load_obj(write("cr.obj", "v 0 0 0\rv 1 0 0\rv 0 1 0\rf -3 -2 -1"));  // no final newline either
    ASSERT_TRUE(cr.ok()) << cr.error();
    EXPECT_EQ(cr->triangle_count(), 1u);
    // Line numbers count \r\n as one line end.
    const std::string path = write("crlf_bad.obj", "v 0 0 0\r\n\r\nv 1 0 0\r\nf 1 2 7\r\n");
    auto bad = load_obj(path);
    ASSERT_FALSE(bad.ok());
    expect_contains(bad.error(), path + ":4: face index 7 out of range (file has 2 vertices)");
}

// ---------------------------------------------------------------------------
// Malformed files: one line, naming the file and the line
// ---------------------------------------------------------------------------

struct BadObj {
    const char* what;
    const char* text;
    int line;
    const char* reason;  ///< part of the message
};

TEST_F(ObjFiles, EachMalformedFileNamesTheFileAndTheLine) {
    const BadObj cases[] = {
        {"bad_number", "v 0 0 0\nv 1 abc 0\n", 2, "bad number 'abc'"},
        {"number_with_junk", "v 0 0 0\n\n# c\nv 1 2 3x\n", 4, "'3x'"},
        {"two_coordinates", "v 0 0\n", 1, "vertex has 2 coordinates"},
        {"no_coordinates", "v 0 0 0\nv\n", 2, "vertex has 0 coordinates"},
        {"nan", "v 0 0 0\nv 0 nan 0\n", 2, "non-finite coordinate 'nan'"},
        {"inf", "v -inf 0 0\n", 1, "non-finite"},
        {"beyond_float", "v 0 0 0\nv 0 0 1e39\n", 2, "non-finite coordinate '1e39'"},
        {"beyond_double", "v 0 0 1e999\n", 1, "non-finite"},
        {"index_too_large", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 999\n", 5,
         "face index 999 out of range (file has 3 vertices)"},
        {"index_zero", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "face index 0 is invalid"},
        {"relative_before_start", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", 4, "face index -4 out of range"},
        {"two_vertex_face", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n", 5, "face has 2 vertices, needs at least 3"},
        {"empty_face", "v 0 0 0\nf\n", 2, "face has 0 vertices"},
        {"text_index", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n", 4, "bad face index 'x'"},
        {"float_index", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2.5 3\n", 4, "bad face index '2.5'"},
        {"zero_texture_index", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/0 2/1 3/1\n", 5, "texture/normal index"},
        {"huge_index", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n", 4, "bad face index"},
        // A forward index is judged against the final count; it comes first here.
        {"forward_out_of_range_first", "f 1 2 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 bad 0\n", 1,
         "face index 9 out of range (file has 4 vertices)"},
        // ...and when it is in range, the later error is the one reported.
        {"forward_in_range", "f 1 2 4\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 bad 0\n", 5, "bad number 'bad'"},
        // Several forward indices: the earliest line whose index exceeds the count.
        {"forward_several", "f 1 2 5\nf 1 2 4\nf 1 2 6\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 1 1 1\n", 3,
         "face index 6 out of range (file has 5 vertices)"},
    };
    for (const BadObj& c : cases) {
        SCOPED_TRACE(c.what);
        const std::string path = write(std::string(c.what) + ".obj", c.text);
        auto mesh = load_obj(path);
        ASSERT_FALSE(mesh.ok());
        const std::string& message = mesh.error();
        expect_contains(message, path + ":" + std::to_string(c.line) + ": ");
        expect_contains(message, c.reason);
        EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    }
}

TEST_F(ObjFiles, MissingFileIsAnError) {
    const std::string path = (dir_ / "nothing_here.obj").string();
    auto mesh = load_obj(path);
    ASSERT_FALSE(mesh.ok());
    expect_contains(mesh.error(), path + ": no such file");
}

TEST_F(ObjFiles, DirectoryIsAnError) {
    auto mesh = load_obj(dir_.string());
    ASSERT_FALSE(mesh.ok());
    expect_contains(mesh.error(), dir_.string() + ": is a directory");
}

TEST_F(ObjFiles, EmptyFileIsAnError) {
    const std::string path = write("empty.obj", "");
    auto mesh = load_obj(path);
    ASSERT_FALSE(mesh.ok());
    expect_contains(mesh.error(), path + ": empty file");
    auto blank = load_obj(write("blank.obj", "\n  \r\n\t\n"));
    ASSERT_FALSE(blank.ok());
    expect_contains(blank.error(), "empty file");
}

TEST_F(ObjFiles, FileWithOnlyVerticesHasNoTriangles) {
    const std::string path = write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    auto mesh = load_obj(path);
    ASSERT_FALSE(mesh.ok());
    expect_contains(mesh.error(), path + ": no triangles (3 vertices, no faces)");
}

TEST_F(ObjFiles, BinaryGarbageIsAnErrorNotACrash) {
    std::string bytes;
    for (int i = 0; i < 4096; ++i) bytes.push_back(char((i * 7919 + 13) & 0xff));
    auto mesh = load_obj(write("garbage.obj", bytes));
    EXPECT_FALSE(mesh.ok());
    auto mixed = load_obj(write("mixed.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n") + bytes));
    if (!mixed.ok()) expect_contains(mixed.error(), "mixed.obj");
}

// ---------------------------------------------------------------------------
// Real meshes (../shared/assets, see its README.md)
// ---------------------------------------------------------------------------

namespace {

struct RealMesh {
    const char* file;
    size_t triangles;
    size_t vertices;
    Vec3 lo, hi;  ///< as printed in the README (about 6 significant digits)
};

void expect_matches_readme(const RealMesh& expected) {
    SCOPED_TRACE(expected.file);
    if (!test::shared_asset_exists(expected.file)) GTEST_SKIP() << "shared asset missing: " << expected.file;
    auto mesh = load_obj(test::shared_asset(expected.file));
    ASSERT_TRUE(mesh.ok()) << mesh.error();
    EXPECT_EQ(mesh->triangle_count(), expected.triangles);
    EXPECT_EQ(mesh->positions.size(), expected.vertices);
    const Aabb box = mesh->bounds();
    for (int axis = 0; axis < 3; ++axis) {
        // The README rounds to ~6 significant digits of the largest coordinate.
        const float tolerance = 1e-5f * std::max(1.0f, std::max(std::abs(expected.lo[axis]), std::abs(expected.hi[axis])));
        EXPECT_NEAR(box.lo[axis], expected.lo[axis], tolerance) << "axis " << axis;
        EXPECT_NEAR(box.hi[axis], expected.hi[axis], tolerance) << "axis " << axis;
    }
}

}  // namespace

TEST(RealObj, BunnyHasItsTrianglesAndBounds) {
    expect_matches_readme({"bunny.obj", 69451, 34834, {-0.09469f, 0.032987f, -0.061874f}, {0.061009f, 0.187321f, 0.0588f}});
}

TEST(RealObj, CornellBoxOriginal) {
    expect_matches_readme({"cornellbox_original.obj", 36, 64, {-1.02f, 0.0f, -1.04f}, {1.0f, 1.99f, 0.99f}});
}

TEST(RealObj, EveryMeshInTheReadmeSlow) {
    const RealMesh meshes[] = {
        {"teapot_mcguire.obj", 15704, 7850, {-71.8925f, 0.0f, -47.9284f}, {82.294f, 79.0066f, 47.9284f}},
        {"armadillo.obj", 345944, 172974, {-63.5001f, -54.2415f, -57.7145f}, {63.5001f, 97.0804f, 57.714f}},
        {"conference.obj", 331179, 194399, {-1020.13f, -2.7924f, -1055.66f}, {1685.81f, 650.293f, 668.489f}},
        {"sibenik.obj", 75284, 40979, {-20.1411f, -15.3123f, -8.4968f}, {20.1411f, 15.3f, 8.4968f}},
        {"sponza_dabrovic.obj", 66450, 60848, {-17.4028f, -0.906689f, -7.79851f}, {17.4172f, 15.6533f, 7.80149f}},
        {"lost_empire.obj", 224998, 97077, {-37.0f, 0.0f, -82.0f}, {38.0f, 49.0f, 83.0f}},
        {"cornellbox_sphere.obj", 2188, 1116, {-1.02f, 0.0f, -1.04f}, {1.0f, 1.59f, 0.99f}},
        {"teapot_in_sibenik.obj", 132500, 69907, {-20.1411f, -15.3123f, -8.4968f}, {20.1411f, 15.3f, 8.4968f}},
    };
    for (const RealMesh& m : meshes) expect_matches_readme(m);
}

// ---------------------------------------------------------------------------
// load_scene dispatch
// ---------------------------------------------------------------------------

TEST_F(ObjFiles, LoadSceneSendsBuiltinsToMakeBuiltinAndPathsToLoadObj) {
    auto cube = load_scene("builtin:cube");
    ASSERT_TRUE(cube.ok()) << cube.error();
    EXPECT_EQ(cube->name, "builtin:cube");
    EXPECT_EQ(cube->triangle_count(), 12u);

    const std::string path = write("one.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    auto one = load_scene(path);
    ASSERT_TRUE(one.ok()) << one.error();
    EXPECT_EQ(one->name, path);

    auto none = load_scene("");
    ASSERT_FALSE(none.ok());
    EXPECT_FALSE(none.error().empty());
}

// ---------------------------------------------------------------------------
// What editors write, and what no ray tracer can show faithfully

TEST_F(ObjFiles, AUtf8ByteOrderMarkIsNotPartOfTheFirstLine) {
    auto mesh = load_obj(write("bom.obj", "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    ASSERT_TRUE(mesh) << mesh.error();
    EXPECT_EQ(mesh->positions.size(), 3u);
    EXPECT_EQ(mesh->triangle_count(), 1u);
}

TEST_F(ObjFiles, ALineThatLooksLikeAVertexButIsNotOneIsAnError) {
    // Skipped as an unknown statement, "v1 0 0" would shift every later index by one.
    auto mesh = load_obj(write("v1.obj", "v 0 0 0\nv1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\n"));
    ASSERT_FALSE(mesh);
    expect_contains(mesh.error(), "v1.obj:2:");
    expect_contains(mesh.error(), "'v1'");
    auto face = load_obj(write("f1.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf1 2 3\n"));
    ASSERT_FALSE(face);
    expect_contains(face.error(), "f1.obj:4:");
    // vt, vn and vp are statements of their own.
    EXPECT_TRUE(load_obj(write("vt.obj", "v 0 0 0\nvt 0 0\nvn 0 0 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")));
}

TEST_F(ObjFiles, CoordinatesBeyondTheFloatTestsRangeAreRefusedWithTheLimit) {
    // Möller–Trumbore's t multiplies three lengths: at 1e13 it overflows float and the
    // ray caster would miss what the rasterizer draws.
    auto mesh = load_obj(write("big.obj", "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n"));
    ASSERT_FALSE(mesh);
    expect_contains(mesh.error(), "big.obj:2:");
    expect_contains(mesh.error(), "1e+12");
    EXPECT_TRUE(load_obj(write("ok.obj", "v 0 0 0\nv 1e12 0 0\nv 0 -1e12 0\nf 1 2 3\n")));
}

TEST_F(ObjFiles, ASceneWhoseTrianglesAllHaveZeroAreaIsAnError) {
    const std::string path = write("flat.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\nf 1 1 1\n");
    auto loaded = load_obj(path);
    ASSERT_TRUE(loaded) << loaded.error();  // the file is well formed ...
    EXPECT_EQ(count_degenerate_triangles(*loaded), 2u);
    auto scene = load_scene(path);  // ... but there is nothing to draw
    ASSERT_FALSE(scene);
    expect_contains(scene.error(), "all 2 triangles have zero area");
}

TEST_F(ObjFiles, SomeZeroAreaTrianglesAreCountedInANote) {
    const std::string path = write("some.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n");
    auto scene = load_scene(path);
    ASSERT_TRUE(scene) << scene.error();
    auto note = degenerate_note(*scene);
    ASSERT_TRUE(note);
    expect_contains(*note, "1 of 2 triangles have zero area");
    EXPECT_FALSE(degenerate_note(*load_scene("builtin:cube")));
}

TEST_F(ObjFiles, ASceneTooSmallForFloatIsRefusedWithTheLimit) {
    auto scene = load_scene(write("tiny.obj", "v 0 0 0\nv 1e-15 0 0\nv 0 1e-15 0\nf 1 2 3\n"));
    ASSERT_FALSE(scene);
    expect_contains(scene.error(), "less than 1e-12");
    EXPECT_TRUE(load_scene(write("small.obj", "v 0 0 0\nv 1e-9 0 0\nv 0 1e-9 0\nf 1 2 3\n")));
}

// ---------------------------------------------------------------------------
// Big files: read in pieces of about 8 MiB, in parallel
// ---------------------------------------------------------------------------

namespace {

/// A ~25 MB OBJ (several pieces) with its expected mesh: a strip of quads, each
/// quad's two vertices then its face, so faces refer back into earlier pieces; the
/// first face refers forward to the last vertices; lines end in "\r\n" every
/// seventh line and carry a comment every eleventh.
struct BigObj {
    std::string text;
    std::vector<Vec3> positions;
    std::vector<Tri> triangles;
    std::vector<size_t> face_lines;  ///< the line number of each quad's face
    size_t lines = 0;
};

const BigObj& big_obj() {
    static const BigObj obj = [] {
        constexpr size_t kQuads = 420000;
        BigObj o;
        auto line = [&](const std::string& body) {
            ++o.lines;
            o.text += body;
            if (o.lines % 11 == 0) o.text += " # note";
            o.text += o.lines % 7 == 0 ? "\r\n" : "\n";
        };
        const size_t vertices = 2 * (kQuads + 1);
        line("o strip");
        line("f 1 2 " + std::to_string(vertices) + " " + std::to_string(vertices - 1));  // forward
        o.triangles.push_back({0, 1, uint32_t(vertices - 1)});
        o.triangles.push_back({0, uint32_t(vertices - 1), uint32_t(vertices - 2)});
        o.face_lines.push_back(o.lines);
        for (size_t q = 0; q <= kQuads; ++q) {
            for (int side = 0; side < 2; ++side) {
                const Vec3 p{float(q) * 0.25f, float(side), float(q % 13) * 0.125f};
                o.positions.push_back(p);
                char buffer[96];
                std::snprintf(buffer, sizeof buffer, "v %.9g %.9g %.9g", double(p.x), double(p.y), double(p.z));
                line(buffer);
            }
            if (q == 0) continue;
            const uint32_t a = uint32_t(2 * q - 2), b = a + 1, c = a + 3, d = a + 2;  // 0-based
            line("f " + std::to_string(a + 1) + " " + std::to_string(b + 1) + " " + std::to_string(c + 1) + " " +
                 std::to_string(d + 1));
            o.triangles.push_back({a, b, c});
            o.triangles.push_back({a, c, d});
            o.face_lines.push_back(o.lines);
        }
        return o;
    }();
    return obj;
}

void expect_mesh(const Mesh& mesh, const BigObj& obj) {
    ASSERT_EQ(mesh.positions.size(), obj.positions.size());
    ASSERT_EQ(mesh.indices.size(), obj.triangles.size());
    for (size_t i = 0; i < obj.positions.size(); ++i) ASSERT_EQ(mesh.positions[i], obj.positions[i]) << "vertex " << i;
    for (size_t i = 0; i < obj.triangles.size(); ++i) ASSERT_EQ(mesh.indices[i], obj.triangles[i]) << "triangle " << i;
}

/// The text with line `number` (1-based) replaced by `body`.
std::string with_line(std::string text, size_t number, const std::string& body) {
    size_t begin = 0;
    for (size_t n = 1; n < number; ++n) begin = text.find('\n', begin) + 1;
    size_t end = begin;
    while (text[end] != '\n' && text[end] != '\r') ++end;
    return text.replace(begin, end - begin, body);
}

}  // namespace

TEST(BigObj, ReadInPiecesItGivesEveryVertexAndTriangleInFileOrder) {
    const BigObj& obj = big_obj();
    ASSERT_GT(obj.text.size(), size_t(24) << 20) << "must span several pieces";
    auto mesh = parse_obj(obj.text, "big.obj");
    ASSERT_TRUE(mesh) << mesh.error();
    expect_mesh(*mesh, obj);
}

TEST(BigObj, AFileWithRelativeIndicesIsReadAsOnePieceToTheSameMesh) {
    // The last face again with negative indices: the same corners, counted back from
    // the latest vertex (tinyobjloader resolves them against the vertices it has read).
    const BigObj& obj = big_obj();
    const std::string text = with_line(obj.text, obj.face_lines.back(), "f -4 -3 -1 -2");
    auto mesh = parse_obj(text, "big.obj");
    ASSERT_TRUE(mesh) << mesh.error();
    expect_mesh(*mesh, obj);
}

TEST(BigObj, AnErrorInALaterPieceNamesItsLineInTheWholeFile) {
    const BigObj& obj = big_obj();
    const size_t line = obj.face_lines[obj.face_lines.size() - 1000] - 1;  // a vertex line near the end
    auto mesh = parse_obj(with_line(obj.text, line, "v 1 2 oops"), "big.obj");
    ASSERT_FALSE(mesh);
    EXPECT_EQ(mesh.error(), "big.obj:" + std::to_string(line) + ": bad number 'oops' in vertex");
}

TEST(BigObj, TheEarliestProblemWinsAcrossPieces) {
    const BigObj& obj = big_obj();
    const size_t late = obj.face_lines[obj.face_lines.size() - 10];
    const size_t early = obj.face_lines[5];
    const std::string too_far = "face index 999999999 out of range (file has " + std::to_string(obj.positions.size()) +
                                " vertices)";
    // A forward index beyond the file on an early line, a bad face on a late one.
    std::string text = with_line(with_line(obj.text, early, "f 1 2 999999999"), late, "f 1 2");
    auto mesh = parse_obj(text, "big.obj");
    ASSERT_FALSE(mesh);
    EXPECT_EQ(mesh.error(), "big.obj:" + std::to_string(early) + ": " + too_far);
    // The other way round: the bad face first.
    text = with_line(with_line(obj.text, early, "f 1 2"), late, "f 1 2 999999999");
    mesh = parse_obj(text, "big.obj");
    ASSERT_FALSE(mesh);
    EXPECT_EQ(mesh.error(), "big.obj:" + std::to_string(early) + ": face has 2 vertices, needs at least 3");
}

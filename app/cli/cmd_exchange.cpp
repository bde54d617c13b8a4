// `accelviz export SCENE [structure flags] --out FILE`: one of our structures in the
// exchange format (docs/structure-format.md).
// `accelviz check SCENE FILE`: is a structure from a file (a student's) valid over the
// scene, and how good is it, side by side with ours (core/exchange/structure_check.h).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli/accel_flags.h"
#include "app/cli/camera_flags.h"
#include "app/cli/commands.h"
#include "app/cli/flag_checks.h"
#include "app/cli/progress.h"
#include "app/cli/ray_batch.h"
#include "app/cli/scene_input.h"
#include "core/accel/bvh.h"
#include "core/exchange/pixel_hits.h"
#include "core/exchange/structure_check.h"
#include "core/exchange/structure_file.h"

namespace accelviz::cli {
namespace {

struct ExportOptions {
    std::string scene;
    std::string out;
    AccelConfig accel;
};

int run_export(const ExportOptions& opt) {
    auto fail = [](const std::string& message) {
        std::cerr << "accelviz export: " << message << "\n";
        return 1;
    };
    if (opt.accel.type != AccelType::Bvh && opt.accel.type != AccelType::Kd && opt.accel.type != AccelType::Grid)
        return fail("--accel " + std::string(to_string(opt.accel.type)) +
                    ": the exchange format holds a BVH, a KD tree or a grid (--accel bvh|kd|grid)");
    auto mesh = load_scene_noting(opt.scene, "export");
    if (!mesh) return fail(mesh.error());
    auto accel = [&] {
        const StepProgress progress("export", "building " + std::string(to_string(opt.accel.type)));
        return build_accelerator(*mesh, opt.accel);
    }();
    if (!accel) return fail(accel.error());
    print_memory_budget_note(**accel, "export");
    auto crc = mesh_crc32(opt.scene, *mesh);
    if (!crc) return fail(crc.error());
    auto file = export_structure(**accel, *mesh, MeshReference{opt.scene, mesh->triangle_count(), *crc});
    if (!file) return fail(file.error());
    if (auto err = write_structure_file(*file, opt.out)) return fail(err->message);
    const size_t nodes = file->type == AccelType::Bvh ? file->bvh_nodes.size()
                         : file->type == AccelType::Kd ? file->kd_nodes.size()
                                                       : file->cells.size();
    std::printf("%s: %s over %s (%zu triangles), %zu %s\n", opt.out.c_str(), (*accel)->name().c_str(),
                opt.scene.c_str(), mesh->triangle_count(), nodes,
                file->type == AccelType::Grid ? "non-empty cells" : "nodes");
    return 0;
}

struct CheckOptions {
    std::string scene;
    std::string tree;
    float cost_trav = 1.0f, cost_isect = 1.0f;
    int width = 320, height = 240;
    size_t max_problems = 50;
    bool json = false;
    std::string hits;  ///< --hits: a traversal's per-pixel answers to compare
    CameraFlags camera;
};

const char* kind_words(const StructureFile& f) {
    switch (f.type) {
        case AccelType::Kd: return "a KD tree";
        case AccelType::Grid: return "a uniform grid";
        default: return "a BVH";
    }
}

/// Our structure to set beside the file's: the same kind with our defaults (a BVH as
/// wide as the file's widest node).
AccelConfig ours_like(const StructureFile& f) {
    AccelConfig c;
    c.type = f.type;
    if (f.type == AccelType::Bvh) c.bvh.width = f.max_arity() <= 2 ? 2 : f.max_arity() <= 4 ? 4 : 8;
    return c;
}

nlohmann::ordered_json figures_json(const StructureFigures& fig) {
    nlohmann::ordered_json j;
    j["nodes"] = fig.nodes;
    j["interior"] = fig.interior;
    j["leaves"] = fig.leaves;
    j["empty_leaves"] = fig.empty_leaves;
    j["depth"] = fig.depth;
    j["avg_children"] = fig.avg_children;
    j["references_per_triangle"] = fig.references;
    j["sah_cost"] = fig.sah_cost;
    j["leaf_sizes"] = fig.leaf_sizes;
    j["rays"] = fig.rays;
    j["nodes_per_ray"] = fig.nodes_per_ray;
    j["box_tests_per_ray"] = fig.box_tests_per_ray;
    j["triangle_tests_per_ray"] = fig.triangle_tests_per_ray;
    j["mismatches"] = fig.mismatches;
    return j;
}

/// "1: 120, 2: 340, ..." for the non-zero sizes (the first 12, then "...").
std::string leaf_sizes_words(const std::vector<uint64_t>& sizes) {
    std::string s;
    int shown = 0;
    for (size_t k = 0; k < sizes.size(); ++k) {
        if (sizes[k] == 0) continue;
        if (shown++ == 12) return s + ", ...";
        s += (s.empty() ? "" : ", ") + std::to_string(k) + ": " + std::to_string(sizes[k]);
    }
    return s.empty() ? "none" : s;
}

/// The trace command that steps pixel (x, y)'s ray as check saw it: the same scene,
/// image and camera, through the file's structure when it is valid.
/// (`window`: the command that opens the window with the stepper on that ray instead.)
std::string trace_command(const CheckOptions& opt, int x, int y, bool through_tree, bool window = false) {
    std::string c = (window ? "accelviz " : "accelviz trace ") + opt.scene + " --pixel " + std::to_string(x) + "," +
                    std::to_string(y) + " --width " + std::to_string(opt.width) + " --height " +
                    std::to_string(opt.height);
    if (!opt.camera.eye.empty()) c += " --eye " + opt.camera.eye;
    if (!opt.camera.target.empty()) c += " --target " + opt.camera.target;
    if (!opt.camera.up.empty()) c += " --up " + opt.camera.up;
    if (opt.camera.fov) c += " --fov " + std::to_string(*opt.camera.fov);
    if (through_tree) c += " --structure " + opt.tree;
    return c;
}

/// --hits: the file's per-pixel answers against brute force's (through `reference`,
/// our binary BVH, which is exact against it); prints the pixels that differ with a trace command each, and
/// puts the comparison in out["hits"].
std::optional<Error> compare_hits(const CheckOptions& opt, const Mesh& mesh, const Camera& camera,
                                  const Accelerator& reference, bool tree_valid, nlohmann::ordered_json& out) {
    std::ifstream in(opt.hits, std::ios::binary);
    if (!in) return Error{opt.hits + ": cannot open"};
    std::ostringstream text;
    text << in.rdbuf();
    auto hits = parse_pixel_hits(std::move(text).str(), opt.width, opt.height);
    if (!hits) return Error{opt.hits + ": " + hits.error()};
    const PixelHitComparison cmp = compare_pixel_hits(*hits, camera, mesh, reference);
    nlohmann::ordered_json differ = nlohmann::ordered_json::array();
    auto hit_json = [](uint32_t tri, float t) {
        return tri == Hit::kNoHit ? nlohmann::ordered_json{{"triangle", -1}}
                                  : nlohmann::ordered_json{{"triangle", tri}, {"t", t}};
    };
    for (size_t i = 0; i < cmp.differ.size() && i < opt.max_problems; ++i) {
        const PixelDisagreement& d = cmp.differ[i];
        differ.push_back({{"pixel", {d.yours.x, d.yours.y}},
                          {"yours", hit_json(d.yours.tri, d.yours.t)},
                          {"right", hit_json(d.right.tri, d.right.t)},
                          {"trace", trace_command(opt, d.yours.x, d.yours.y, tree_valid)},
                          {"window", trace_command(opt, d.yours.x, d.yours.y, tree_valid, true)}});
    }
    out["hits"] = {{"file", opt.hits}, {"pixels", cmp.pixels}, {"agree", cmp.agree}, {"ties", cmp.ties},
                   {"differ_count", cmp.differ.size()}, {"differ", differ}};
    if (opt.json) return std::nullopt;
    auto words = [](uint32_t tri, float t) {
        char buf[64];
        if (tri == Hit::kNoHit) return std::string("a miss");
        std::snprintf(buf, sizeof buf, "triangle %u at t = %.7g", tri, t);
        return std::string(buf);
    };
    std::printf("%s: %llu pixels; %llu agree with brute force%s, %zu differ%s\n", opt.hits.c_str(),
                (unsigned long long)cmp.pixels, (unsigned long long)cmp.agree,
                cmp.ties ? (" (" + std::to_string(cmp.ties) + " by a tie: another triangle at the same t)").c_str() : "",
                cmp.differ.size(), cmp.differ.empty() ? "" : ":");
    for (size_t i = 0; i < cmp.differ.size() && i < opt.max_problems; ++i) {
        const PixelDisagreement& d = cmp.differ[i];
        std::printf("  pixel (%d, %d): yours %s; brute force: %s\n    %s\n    %s   (in the window)\n", d.yours.x,
                    d.yours.y, words(d.yours.tri, d.yours.t).c_str(), words(d.right.tri, d.right.t).c_str(),
                    trace_command(opt, d.yours.x, d.yours.y, tree_valid).c_str(),
                    trace_command(opt, d.yours.x, d.yours.y, tree_valid, true).c_str());
    }
    if (cmp.differ.size() > opt.max_problems)
        std::printf("  ... and %zu more (--max-problems)\n", cmp.differ.size() - opt.max_problems);
    return std::nullopt;
}

int run_check(const CheckOptions& opt) {
    auto fail = [](const std::string& message) {
        std::cerr << "accelviz check: " << message << "\n";
        return 1;
    };
    auto mesh = load_scene_noting(opt.scene, "check");
    if (!mesh) return fail(mesh.error());
    auto file = read_structure_file(opt.tree);
    if (!file) return fail(file.error());
    auto crc = mesh_crc32(opt.scene, *mesh);
    if (!crc) return fail(crc.error());
    const StructureCheck check = check_structure(*file, *mesh, *crc, opt.max_problems);

    nlohmann::ordered_json out;
    out["tree"] = opt.tree;
    out["scene"] = opt.scene;
    out["triangles"] = mesh->triangle_count();
    out["type"] = std::string(to_string(file->type));
    if (file->type == AccelType::Bvh) out["arity"] = file->max_arity();
    out["builder"] = file->builder;
    out["valid"] = check.valid();
    out["problem_count"] = check.problem_count;
    nlohmann::ordered_json problems = nlohmann::ordered_json::array();
    for (const StructureProblem& p : check.problems) {
        nlohmann::ordered_json j;
        j["node"] = p.node ? nlohmann::ordered_json(*p.node) : nlohmann::ordered_json(nullptr);
        j["message"] = p.message;
        problems.push_back(j);
    }
    out["problems"] = problems;
    if (!opt.json) {
        std::printf("%s: %s%s over %s (%zu triangles)%s%s\n", opt.tree.c_str(), kind_words(*file),
                    file->type == AccelType::Bvh ? (" of arity " + std::to_string(file->max_arity())).c_str() : "",
                    opt.scene.c_str(), mesh->triangle_count(), file->builder.empty() ? "" : ", built by ",
                    file->builder.c_str());
        if (!check.valid()) {
            std::printf("NOT VALID: %llu problem%s\n", (unsigned long long)check.problem_count,
                        check.problem_count == 1 ? "" : "s");
            for (const StructureProblem& p : check.problems) std::printf("  %s\n", p.message.c_str());
            if (check.problem_count > check.problems.size())
                std::printf("  ... and %llu more (--max-problems)\n",
                            (unsigned long long)(check.problem_count - check.problems.size()));
        }
    }
    auto camera = opt.camera.resolve(mesh->bounds());
    if (!camera) return fail(camera.error());
    // The right answers: brute force's, through our binary BVH (exact against it), built
    // once when first needed (ours is that BVH for a binary file).
    std::shared_ptr<const Accelerator> reference;
    auto exact_reference = [&]() -> Expected<std::shared_ptr<const Accelerator>> {
        if (reference) return reference;
        AccelConfig bvh;
        bvh.type = AccelType::Bvh;
        auto built = build_accelerator(*mesh, bvh);
        if (built) reference = *built;
        return built;
    };
    bool hits_differ = false;
    if (!opt.hits.empty()) {
        auto exact = exact_reference();
        if (!exact) return fail(exact.error());
        if (auto err = compare_hits(opt, *mesh, Camera(*camera, opt.width, opt.height), **exact, check.valid(), out))
            return fail(err->message);
        hits_differ = !out["hits"]["differ"].empty();
    }
    if (!check.valid()) {
        if (opt.json) std::cout << out.dump(1) << "\n";
        return 1;
    }

    // Measured: the file's structure and ours, through our traversal, on the camera's rays.
    const std::vector<Ray> rays = camera_rays(Camera(*camera, opt.width, opt.height));
    auto theirs = structure_accelerator(*file, *mesh);
    if (!theirs) return fail(theirs.error());
    const AccelConfig ours_config = ours_like(*file);
    auto ours = [&] {
        const StepProgress progress("check", "building ours");
        return build_accelerator(*mesh, ours_config);
    }();
    if (!ours) return fail(ours.error());
    auto ours_file = export_structure(**ours, *mesh, file->mesh);
    if (!ours_file) return fail(ours_file.error());
    const SahCosts costs{opt.cost_trav, opt.cost_isect};
    if (!reference && structure_if<Bvh>(**ours)) reference = *ours;
    if (auto exact = exact_reference(); !exact) return fail(exact.error());
    const StructureFigures yours_fig = [&] {
        const StepProgress progress("check", "tracing " + std::to_string(rays.size()) + " rays through the file's tree");
        return measure_structure(*file, *mesh, **theirs, rays, *reference, costs);
    }();
    const StructureFigures ours_fig = measure_structure(*ours_file, *mesh, **ours, rays, *reference, costs);
    const std::string ours_label = (*ours)->name() + " " + (*ours)->config().dump();
    if (opt.json) {
        out["costs"] = {{"trav", opt.cost_trav}, {"isect", opt.cost_isect}};
        out["image"] = {opt.width, opt.height};
        out["yours"] = figures_json(yours_fig);
        nlohmann::ordered_json o = figures_json(ours_fig);
        o["config"] = (*ours)->config();
        out["ours"] = o;
        std::cout << out.dump(1) << "\n";
        return hits_differ ? 1 : 0;
    }
    std::printf("valid. Measured with C_trav = %g, C_isect = %g, on the %d x %d rays of the camera:\n", opt.cost_trav,
                opt.cost_isect, opt.width, opt.height);
    std::printf("%-24s %14s %14s\n", "", "your tree", "ours");
    auto row = [](const char* what, double a, double b, const char* format) {
        char x[32], y[32];
        std::snprintf(x, sizeof x, format, a);
        std::snprintf(y, sizeof y, format, b);
        std::printf("%-24s %14s %14s\n", what, x, y);
    };
    row("SAH cost", yours_fig.sah_cost, ours_fig.sah_cost, "%.2f");
    row(file->type == AccelType::Grid ? "cells" : "nodes", double(yours_fig.nodes), double(ours_fig.nodes), "%.0f");
    row(file->type == AccelType::Grid ? "empty cells" : "leaves",
        double(file->type == AccelType::Grid ? yours_fig.empty_leaves : yours_fig.leaves),
        double(file->type == AccelType::Grid ? ours_fig.empty_leaves : ours_fig.leaves), "%.0f");
    if (file->type != AccelType::Grid) {
        row("depth", yours_fig.depth, ours_fig.depth, "%.0f");
        if (file->type == AccelType::Bvh) row("children per node", yours_fig.avg_children, ours_fig.avg_children, "%.2f");
    }
    if (file->type != AccelType::Bvh)
        row("references / triangle", yours_fig.references, ours_fig.references, "%.2f");
    row(file->type == AccelType::Grid ? "cells visited / ray" : "nodes visited / ray", yours_fig.nodes_per_ray,
        ours_fig.nodes_per_ray, "%.2f");
    if (file->type == AccelType::Bvh) row("box tests / ray", yours_fig.box_tests_per_ray, ours_fig.box_tests_per_ray, "%.2f");
    row("triangle tests / ray", yours_fig.triangle_tests_per_ray, ours_fig.triangle_tests_per_ray, "%.2f");
    std::printf("your leaf sizes (size: %s): %s\n", file->type == AccelType::Grid ? "non-empty cells" : "leaves",
                leaf_sizes_words(yours_fig.leaf_sizes).c_str());
    std::printf("ours: %s\n", ours_label.c_str());
    if (yours_fig.mismatches > 0)
        std::printf("note: %llu of %zu rays found another closest hit through your tree than brute force: a "
                    "triangle that only touches a cell may need listing there too\n",
                    (unsigned long long)yours_fig.mismatches, rays.size());
    return hits_differ ? 1 : 0;
}

}  // namespace

Command register_export(CLI::App& app) {
    auto opt = std::make_shared<ExportOptions>();
    CLI::App* sub = app.add_subcommand(
        "export", "Write one of our structures (a BVH of any width, a KD tree or a grid) in the exchange format "
                  "that check reads (docs/structure-format.md)");
    sub->add_option("scene", opt->scene, "OBJ file or builtin:NAME")->required();
    sub->add_option("--out", opt->out, "Where to write: FILE.json, or FILE.avs for the compact binary variant")
        ->required();
    add_accel_flags(*sub, opt->accel);
    return {sub, [opt] { return run_export(*opt); }};
}

Command register_check(CLI::App& app) {
    auto opt = std::make_shared<CheckOptions>();
    CLI::App* sub = app.add_subcommand(
        "check", "Check a structure from a file (e.g. a student's BVH): what is wrong with it, node by node, or "
                 "how good it is beside ours. Exit code 0 only when it is valid (and, with --hits, every pixel agrees)");
    sub->add_option("scene", opt->scene, "The OBJ file or builtin:NAME the structure was built over")->required();
    sub->add_option("tree", opt->tree, "The structure: JSON or binary (docs/structure-format.md)")->required();
    sub->add_option("--cost-trav", opt->cost_trav, "C_trav of the SAH cost reported for both trees")
        ->check(number_between(0.0, 1e6))
        ->capture_default_str();
    sub->add_option("--cost-isect", opt->cost_isect, "C_isect of the SAH cost reported for both trees")
        ->check(number_between(1e-6, 1e6))
        ->capture_default_str();
    sub->add_option("--width", opt->width, "Rays measured: the camera's image width")
        ->check(whole_number(1, 16384))
        ->capture_default_str();
    sub->add_option("--height", opt->height, "... and height")->check(whole_number(1, 16384))->capture_default_str();
    sub->add_option("--max-problems", opt->max_problems, "Problems listed at most (all are counted)")
        ->check(whole_number(1, 1 << 30))
        ->capture_default_str();
    sub->add_flag("--json", opt->json, "Everything as JSON (for autograders)");
    sub->add_option("--hits", opt->hits,
                    "CSV of your traversal's answers, lines x,y,triangle,t (-1: a miss) for the camera's --width x "
                    "--height pixels: the pixels that differ from brute force, each with the trace command that "
                    "steps its ray (exit code 1 when any differ)");
    opt->camera.add_to(*sub);
    return {sub, [opt] { return run_check(*opt); }};
}

}  // namespace accelviz::cli

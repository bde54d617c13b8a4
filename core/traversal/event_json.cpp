#include "core/traversal/event_json.h"

#include <cmath>
#include <string>

namespace accelviz {

nlohmann::json float_to_json(float value) {
    if (std::isnan(value)) return "nan";
    if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
    return value;
}

namespace {
nlohmann::json tri_to_json(uint32_t tri) { return tri == Hit::kNoHit ? nlohmann::json(nullptr) : nlohmann::json(tri); }
}  // namespace

nlohmann::json to_json(const TraversalEvent& e) {
    nlohmann::json j = {{"kind", to_string(e.kind)}};
    auto interval = [&] {
        j["t_enter"] = float_to_json(e.t_enter);
        j["t_exit"] = float_to_json(e.t_exit);
    };
    auto hit_values = [&] {
        j["tri"] = tri_to_json(e.tri);
        j["t"] = float_to_json(e.t);
        j["u"] = float_to_json(e.u);
        j["v"] = float_to_json(e.v);
    };
    switch (e.kind) {
        case EventKind::BoxTest:
            j["node"] = e.node;
            interval();
            j["hit"] = e.hit;
            break;
        case EventKind::VisitNode:
        case EventKind::Push:
        case EventKind::Pop:
            j["node"] = e.node;
            interval();
            break;
        case EventKind::Cull:
            j["node"] = e.node;
            j["reason"] = to_string(e.reason);
            interval();
            break;
        case EventKind::Leaf:
            j["node"] = e.node;
            j["first"] = e.first;
            j["count"] = e.count;
            interval();
            break;
        case EventKind::TriangleTest:
            hit_values();
            j["hit"] = e.hit;
            break;
        case EventKind::NewClosest: hit_values(); break;
        case EventKind::EnterCell:
            j["cell"] = {e.cell[0], e.cell[1], e.cell[2]};
            j["node"] = e.node;
            interval();
            break;
        case EventKind::MailboxSkip: j["tri"] = tri_to_json(e.tri); break;
        case EventKind::HitOutsideCell:
            j["tri"] = tri_to_json(e.tri);
            j["t"] = float_to_json(e.t);
            j["t_exit"] = float_to_json(e.t_exit);
            break;
        case EventKind::SplitPlane:
            j["node"] = e.node;
            j["axis"] = e.axis;
            j["split"] = float_to_json(e.split);
            j["t"] = float_to_json(e.t);
            j["near_first"] = e.near_first;
            break;
        case EventKind::Done:
            j["hit"] = e.hit;
            hit_values();
            break;
    }
    return j;
}

std::string describe(const TraversalEvent& e) {
    const nlohmann::json j = to_json(e);
    std::string line = j["kind"].get<std::string>();
    for (const auto& [key, value] : j.items())
        if (key != "kind") line += "  " + key + "=" + (value.is_string() ? value.get<std::string>() : value.dump());
    return line;
}

nlohmann::json to_json(const std::vector<TraversalEvent>& events) {
    nlohmann::json array = nlohmann::json::array();
    for (const TraversalEvent& e : events) array.push_back(to_json(e));
    return array;
}

nlohmann::json to_json(const Counters& c) {
    return {{"nodes_visited", c.nodes_visited}, {"box_tests", c.box_tests},
            {"triangle_tests", c.triangle_tests}, {"mailbox_skips", c.mailbox_skips},
            {"hits_outside_cell", c.hits_outside_cell}, {"culls", c.culls}};
}

nlohmann::json to_json(const Hit& hit) {
    if (!hit.found()) return {{"hit", false}};
    return {{"hit", true}, {"tri", hit.tri}, {"t", float_to_json(hit.t)}, {"u", float_to_json(hit.u)},
            {"v", float_to_json(hit.v)}};
}

}  // namespace accelviz

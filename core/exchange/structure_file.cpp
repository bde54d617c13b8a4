#include "core/exchange/structure_file.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/accel/bvh.h"
#include "core/accel/kd_tree.h"
#include "core/accel/uniform_grid.h"
#include "core/accel/wide_bvh.h"
#include "core/util/crc32.h"

namespace accelviz {

int StructureFile::max_arity() const {
    size_t most = 0;
    for (const FileBvhNode& n : bvh_nodes)
        if (n.interior) most = std::max(most, n.children.size());
    return int(std::min<size_t>(most, 1u << 30));
}

namespace {

constexpr const char* kFormatName = "accelviz-structure";
constexpr char kBinaryMagic[8] = {'A', 'V', 'Z', 'S', 'T', 'R', 'C', '1'};

const char* type_word(AccelType type) {
    switch (type) {
        case AccelType::Kd: return "kd";
        case AccelType::Grid: return "grid";
        default: return "bvh";
    }
}

// [SECTION] JSON writer: shortest round-trip floats, one node per line.

void put_float(std::string& out, float x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, r.ptr);
}

void put_uint(std::string& out, uint64_t x) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, r.ptr);
}

void put_box(std::string& out, const Aabb& b) {
    out += '[';
    const float v[6] = {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z};
    for (int i = 0; i < 6; ++i) {
        if (i) out += ',';
        put_float(out, v[i]);
    }
    out += ']';
}

template <class Ints>
void put_uints(std::string& out, const Ints& xs) {
    out += '[';
    bool first = true;
    for (auto x : xs) {
        if (!first) out += ',';
        first = false;
        put_uint(out, uint64_t(x));
    }
    out += ']';
}

// [SECTION] JSON reader

/// Where a malformed value is, for the message: "node 12" or "the file".
struct Where {
    std::string what;
};

Error malformed(const Where& at, const std::string& why) { return Error{at.what + ": " + why}; }

std::optional<Error> read_index(const nlohmann::json& j, const Where& at, const char* key, uint64_t& out,
                                uint64_t max = UINT32_MAX) {
    if (!j.is_number_unsigned() || j.get<uint64_t>() > max)
        return malformed(at, std::string("\"") + key + "\" must be a whole number from 0 to " + std::to_string(max));
    out = j.get<uint64_t>();
    return std::nullopt;
}

std::optional<Error> read_ids(const nlohmann::json& j, const Where& at, const char* key, std::vector<uint32_t>& out) {
    if (!j.is_array()) return malformed(at, std::string("\"") + key + "\" must be a list of whole numbers");
    out.reserve(j.size());
    for (const auto& x : j) {
        uint64_t v = 0;
        if (auto e = read_index(x, at, key, v)) return e;
        out.push_back(uint32_t(v));
    }
    return std::nullopt;
}

std::optional<Error> read_box(const nlohmann::json& j, const Where& at, const char* key, Aabb& out) {
    if (!j.is_array() || j.size() != 6 || !std::all_of(j.begin(), j.end(), [](const auto& x) { return x.is_number(); }))
        return malformed(at, std::string("\"") + key + "\" must be 6 numbers: lo x, y, z, then hi x, y, z");
    out.lo = {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
    out.hi = {j[3].get<float>(), j[4].get<float>(), j[5].get<float>()};
    return std::nullopt;
}

const nlohmann::json* member(const nlohmann::json& j, const char* key) {
    const auto it = j.find(key);
    return it == j.end() ? nullptr : &*it;
}

std::optional<Error> require(const nlohmann::json& j, const Where& at, const char* key, const nlohmann::json*& out) {
    out = member(j, key);
    if (!out) return malformed(at, std::string("\"") + key + "\" is missing");
    return std::nullopt;
}

Where node_at(size_t i) { return {"node " + std::to_string(i)}; }

std::optional<Error> read_bvh_json(const nlohmann::json& doc, StructureFile& file) {
    const Where top{"the file"};
    const nlohmann::json* order = nullptr;
    const nlohmann::json* nodes = nullptr;
    if (auto e = require(doc, top, "order", order)) return e;
    if (auto e = read_ids(*order, top, "order", file.order)) return e;
    if (auto e = require(doc, top, "nodes", nodes)) return e;
    if (!nodes->is_array()) return malformed(top, "\"nodes\" must be a list");
    file.bvh_nodes.resize(nodes->size());
    for (size_t i = 0; i < nodes->size(); ++i) {
        const nlohmann::json& j = (*nodes)[i];
        const Where at = node_at(i);
        if (!j.is_object()) return malformed(at, "must be an object");
        FileBvhNode& n = file.bvh_nodes[i];
        const nlohmann::json* box = nullptr;
        if (auto e = require(j, at, "box", box)) return e;
        if (auto e = read_box(*box, at, "box", n.box)) return e;
        if (const nlohmann::json* children = member(j, "children")) {
            if (member(j, "first") || member(j, "count"))
                return malformed(at, "has \"children\" and \"first\"/\"count\": a node is interior or a leaf, not both");
            n.interior = true;
            if (auto e = read_ids(*children, at, "children", n.children)) return e;
        } else {
            const nlohmann::json *first = nullptr, *count = nullptr;
            if (!member(j, "first") && !member(j, "count"))
                return malformed(at, "needs \"children\" (interior) or \"first\" and \"count\" (leaf)");
            if (auto e = require(j, at, "first", first)) return e;
            if (auto e = require(j, at, "count", count)) return e;
            if (auto e = read_index(*first, at, "first", n.first)) return e;
            if (auto e = read_index(*count, at, "count", n.count)) return e;
        }
    }
    return std::nullopt;
}

std::optional<Error> read_kd_json(const nlohmann::json& doc, StructureFile& file) {
    const Where top{"the file"};
    const nlohmann::json *bounds = nullptr, *nodes = nullptr;
    if (auto e = require(doc, top, "bounds", bounds)) return e;
    if (auto e = read_box(*bounds, top, "bounds", file.bounds)) return e;
    if (auto e = require(doc, top, "nodes", nodes)) return e;
    if (!nodes->is_array()) return malformed(top, "\"nodes\" must be a list");
    file.kd_nodes.resize(nodes->size());
    for (size_t i = 0; i < nodes->size(); ++i) {
        const nlohmann::json& j = (*nodes)[i];
        const Where at = node_at(i);
        if (!j.is_object()) return malformed(at, "must be an object");
        FileKdNode& n = file.kd_nodes[i];
        if (const nlohmann::json* triangles = member(j, "triangles")) {
            if (member(j, "axis") || member(j, "children"))
                return malformed(at, "has \"triangles\" and \"axis\"/\"children\": a node is a leaf or split, not both");
            if (auto e = read_ids(*triangles, at, "triangles", n.triangles)) return e;
            continue;
        }
        const nlohmann::json *axis = nullptr, *split = nullptr, *children = nullptr;
        if (auto e = require(j, at, "axis", axis)) return e;
        if (auto e = require(j, at, "split", split)) return e;
        if (auto e = require(j, at, "children", children)) return e;
        uint64_t a = 0;
        if (auto e = read_index(*axis, at, "axis", a, 2)) return e;
        if (!split->is_number()) return malformed(at, "\"split\" must be a number");
        std::vector<uint32_t> ids;
        if (auto e = read_ids(*children, at, "children", ids)) return e;
        if (ids.size() != 2) return malformed(at, "\"children\" must be two nodes: below the plane, above it");
        n.axis = int(a);
        n.split = split->get<float>();
        n.children = {ids[0], ids[1]};
    }
    return std::nullopt;
}

std::optional<Error> read_grid_json(const nlohmann::json& doc, StructureFile& file) {
    const Where top{"the file"};
    const nlohmann::json *bounds = nullptr, *resolution = nullptr, *cells = nullptr;
    if (auto e = require(doc, top, "bounds", bounds)) return e;
    if (auto e = read_box(*bounds, top, "bounds", file.bounds)) return e;
    if (auto e = require(doc, top, "resolution", resolution)) return e;
    std::vector<uint32_t> res;
    if (auto e = read_ids(*resolution, top, "resolution", res)) return e;
    if (res.size() != 3) return malformed(top, "\"resolution\" must be three whole numbers: cells along x, y, z");
    file.resolution = {res[0], res[1], res[2]};
    if (auto e = require(doc, top, "cells", cells)) return e;
    if (!cells->is_array()) return malformed(top, "\"cells\" must be a list");
    file.cells.resize(cells->size());
    for (size_t i = 0; i < cells->size(); ++i) {
        const nlohmann::json& j = (*cells)[i];
        const Where at{"cell entry " + std::to_string(i)};
        if (!j.is_object()) return malformed(at, "must be an object");
        const nlohmann::json *cell = nullptr, *triangles = nullptr;
        if (auto e = require(j, at, "cell", cell)) return e;
        std::vector<uint32_t> ijk;
        if (auto e = read_ids(*cell, at, "cell", ijk)) return e;
        if (ijk.size() != 3) return malformed(at, "\"cell\" must be three whole numbers: x, y, z");
        file.cells[i].cell = {ijk[0], ijk[1], ijk[2]};
        if (auto e = require(j, at, "triangles", triangles)) return e;
        if (auto e = read_ids(*triangles, at, "triangles", file.cells[i].triangles)) return e;
    }
    return std::nullopt;
}

// [SECTION] Binary variant: little-endian fields in the JSON's order.

class ByteWriter {
public:
    template <class T>
    void put(T x) {
        char b[sizeof(T)];
        std::memcpy(b, &x, sizeof(T));
        out.append(b, sizeof(T));
    }
    void put_string(const std::string& s) {
        put(uint32_t(s.size()));
        out += s;
    }
    void put_box(const Aabb& b) {
        for (float v : {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z}) put(v);
    }
    void put_ids(const std::vector<uint32_t>& ids) {
        put(uint64_t(ids.size()));
        for (uint32_t id : ids) put(id);
    }
    std::string out;
};

class ByteReader {
public:
    explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}
    template <class T>
    bool get(T& x) {
        if (bytes_.size() - pos_ < sizeof(T)) return fail();
        std::memcpy(&x, bytes_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return true;
    }
    bool get_string(std::string& s) {
        uint32_t n = 0;
        if (!get(n) || bytes_.size() - pos_ < n) return fail();
        s.assign(bytes_.data() + pos_, n);
        pos_ += n;
        return true;
    }
    bool get_box(Aabb& b) {
        return get(b.lo.x) && get(b.lo.y) && get(b.lo.z) && get(b.hi.x) && get(b.hi.y) && get(b.hi.z);
    }
    /// A count of items of at least `item_bytes` each: no more than the bytes left
    /// could hold (a corrupt count must not allocate gigabytes).
    bool get_count(uint64_t& n, size_t item_bytes) {
        if (!get(n) || n > (bytes_.size() - pos_) / std::max<size_t>(item_bytes, 1)) return fail();
        return true;
    }
    bool get_ids(std::vector<uint32_t>& ids) {
        uint64_t n = 0;
        if (!get_count(n, 4)) return false;
        ids.resize(n);
        for (uint32_t& id : ids) get(id);
        return true;
    }
    bool at_end() const { return pos_ == bytes_.size(); }
    size_t failed_at() const { return failed_at_; }

private:
    bool fail() {
        failed_at_ = pos_;
        return false;
    }
    const std::string& bytes_;
    size_t pos_ = 0, failed_at_ = 0;
};

}  // namespace

std::string structure_json(const StructureFile& f) {
    std::string out;
    out += "{\"format\":\"";
    out += kFormatName;
    out += "\",\"version\":";
    put_uint(out, kStructureFormatVersion);
    out += ",\"type\":\"";
    out += type_word(f.type);
    out += "\",\n\"mesh\":";
    nlohmann::json mesh = {{"path", f.mesh.path}, {"triangles", f.mesh.triangles}};
    if (f.mesh.crc32) {
        char hex[9];
        std::snprintf(hex, sizeof hex, "%08x", *f.mesh.crc32);
        mesh["crc32"] = hex;
    }
    out += mesh.dump();
    if (!f.builder.empty()) out += ",\n\"builder\":" + nlohmann::json(f.builder).dump();
    if (f.type == AccelType::Bvh) {
        out += ",\n\"order\":";
        put_uints(out, f.order);
        out += ",\n\"nodes\":[";
        for (size_t i = 0; i < f.bvh_nodes.size(); ++i) {
            const FileBvhNode& n = f.bvh_nodes[i];
            out += i ? ",\n{\"box\":" : "\n{\"box\":";
            put_box(out, n.box);
            if (n.interior) {
                out += ",\"children\":";
                put_uints(out, n.children);
            } else {
                out += ",\"first\":";
                put_uint(out, n.first);
                out += ",\"count\":";
                put_uint(out, n.count);
            }
            out += '}';
        }
        out += "]}\n";
        return out;
    }
    out += ",\n\"bounds\":";
    put_box(out, f.bounds);
    if (f.type == AccelType::Kd) {
        out += ",\n\"nodes\":[";
        for (size_t i = 0; i < f.kd_nodes.size(); ++i) {
            const FileKdNode& n = f.kd_nodes[i];
            out += i ? ",\n{" : "\n{";
            if (n.is_leaf()) {
                out += "\"triangles\":";
                put_uints(out, n.triangles);
            } else {
                out += "\"axis\":";
                put_uint(out, uint64_t(n.axis));
                out += ",\"split\":";
                put_float(out, n.split);
                out += ",\"children\":";
                put_uints(out, n.children);
            }
            out += '}';
        }
        out += "]}\n";
        return out;
    }
    out += ",\n\"resolution\":";
    put_uints(out, f.resolution);
    out += ",\n\"cells\":[";
    for (size_t i = 0; i < f.cells.size(); ++i) {
        out += i ? ",\n{\"cell\":" : "\n{\"cell\":";
        put_uints(out, f.cells[i].cell);
        out += ",\"triangles\":";
        put_uints(out, f.cells[i].triangles);
        out += '}';
    }
    out += "]}\n";
    return out;
}

Expected<StructureFile> parse_structure_json(const std::string& text) {
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
        return Error{std::string("not JSON: ") + e.what()};
    }
    const Where top{"the file"};
    if (!doc.is_object()) return malformed(top, "must be a JSON object");
    const nlohmann::json* format = member(doc, "format");
    if (!format || *format != kFormatName)
        return malformed(top, std::string("\"format\" must be \"") + kFormatName + "\" (docs/structure-format.md)");
    const nlohmann::json* version = member(doc, "version");
    if (!version || !version->is_number_unsigned()) return malformed(top, "\"version\" must be a whole number");
    if (version->get<uint64_t>() != uint64_t(kStructureFormatVersion))
        return malformed(top, "version " + version->dump() + "; this accelviz reads version " +
                                  std::to_string(kStructureFormatVersion));
    StructureFile file;
    const nlohmann::json* type = member(doc, "type");
    if (!type || !type->is_string()) return malformed(top, "\"type\" must be \"bvh\", \"kd\" or \"grid\"");
    const std::string t = type->get<std::string>();
    if (t == "bvh") file.type = AccelType::Bvh;
    else if (t == "kd") file.type = AccelType::Kd;
    else if (t == "grid") file.type = AccelType::Grid;
    else return malformed(top, "\"type\" is \"" + t + "\"; it must be \"bvh\", \"kd\" or \"grid\"");
    const nlohmann::json* mesh = nullptr;
    if (auto e = require(doc, top, "mesh", mesh)) return *e;
    if (!mesh->is_object()) return malformed(top, "\"mesh\" must be an object with \"triangles\"");
    const Where at_mesh{"\"mesh\""};
    if (const nlohmann::json* path = member(*mesh, "path"); path && path->is_string())
        file.mesh.path = path->get<std::string>();
    const nlohmann::json* triangles = nullptr;
    if (auto e = require(*mesh, at_mesh, "triangles", triangles)) return *e;
    if (auto e = read_index(*triangles, at_mesh, "triangles", file.mesh.triangles)) return *e;
    if (const nlohmann::json* crc = member(*mesh, "crc32")) {
        const std::string hex = crc->is_string() ? crc->get<std::string>() : "";
        uint32_t value = 0;
        const auto r = std::from_chars(hex.data(), hex.data() + hex.size(), value, 16);
        if (hex.size() != 8 || r.ec != std::errc() || r.ptr != hex.data() + hex.size())
            return malformed(at_mesh, "\"crc32\" must be 8 hexadecimal digits");
        file.mesh.crc32 = value;
    }
    if (const nlohmann::json* builder = member(doc, "builder"); builder && builder->is_string())
        file.builder = builder->get<std::string>();
    std::optional<Error> err = file.type == AccelType::Bvh ? read_bvh_json(doc, file)
                               : file.type == AccelType::Kd ? read_kd_json(doc, file)
                                                            : read_grid_json(doc, file);
    if (err) return *err;
    return file;
}

std::string structure_binary(const StructureFile& f) {
    ByteWriter w;
    w.out.append(kBinaryMagic, sizeof kBinaryMagic);
    w.put(uint32_t(kStructureFormatVersion));
    w.put(uint32_t(f.type == AccelType::Bvh ? 0 : f.type == AccelType::Kd ? 1 : 2));
    w.put(uint64_t(f.mesh.triangles));
    w.put(uint32_t(f.mesh.crc32 ? 1 : 0));
    w.put(uint32_t(f.mesh.crc32.value_or(0)));
    w.put_string(f.mesh.path);
    w.put_string(f.builder);
    if (f.type == AccelType::Bvh) {
        w.put_ids(f.order);
        w.put(uint64_t(f.bvh_nodes.size()));
        for (const FileBvhNode& n : f.bvh_nodes) {
            w.put_box(n.box);
            w.put(uint8_t(n.interior));
            if (n.interior) {
                w.put_ids(n.children);
            } else {
                w.put(uint64_t(n.first));
                w.put(uint64_t(n.count));
            }
        }
    } else if (f.type == AccelType::Kd) {
        w.put_box(f.bounds);
        w.put(uint64_t(f.kd_nodes.size()));
        for (const FileKdNode& n : f.kd_nodes) {
            w.put(int8_t(n.axis));
            if (n.is_leaf()) {
                w.put_ids(n.triangles);
            } else {
                w.put(n.split);
                w.put(n.children[0]);
                w.put(n.children[1]);
            }
        }
    } else {
        w.put_box(f.bounds);
        for (uint32_t r : f.resolution) w.put(r);
        w.put(uint64_t(f.cells.size()));
        for (const FileGridCell& c : f.cells) {
            for (uint32_t x : c.cell) w.put(x);
            w.put_ids(c.triangles);
        }
    }
    return std::move(w.out);
}

Expected<StructureFile> parse_structure_binary(const std::string& bytes) {
    if (bytes.size() < sizeof kBinaryMagic || std::memcmp(bytes.data(), kBinaryMagic, sizeof kBinaryMagic) != 0)
        return Error{"not an accelviz binary structure (no AVZSTRC1 at its start)"};
    const std::string body = bytes.substr(sizeof kBinaryMagic);
    ByteReader r(body);
    auto truncated = [&] {
        return Error{"truncated or corrupt at byte " + std::to_string(r.failed_at() + sizeof kBinaryMagic)};
    };
    StructureFile f;
    uint32_t version = 0, type = 0, has_crc = 0, crc = 0;
    uint64_t triangles = 0;
    if (!r.get(version)) return truncated();
    if (version != uint32_t(kStructureFormatVersion))
        return Error{"version " + std::to_string(version) + "; this accelviz reads version " +
                     std::to_string(kStructureFormatVersion)};
    if (!r.get(type) || !r.get(triangles) || !r.get(has_crc) || !r.get(crc) || !r.get_string(f.mesh.path) ||
        !r.get_string(f.builder))
        return truncated();
    if (type > 2) return Error{"unknown structure type " + std::to_string(type) + " (0 bvh, 1 kd, 2 grid)"};
    f.type = type == 0 ? AccelType::Bvh : type == 1 ? AccelType::Kd : AccelType::Grid;
    f.mesh.triangles = triangles;
    if (has_crc) f.mesh.crc32 = crc;
    uint64_t n = 0;
    if (f.type == AccelType::Bvh) {
        if (!r.get_ids(f.order) || !r.get_count(n, 25)) return truncated();
        f.bvh_nodes.resize(n);
        for (FileBvhNode& node : f.bvh_nodes) {
            uint8_t interior = 0;
            if (!r.get_box(node.box) || !r.get(interior)) return truncated();
            node.interior = interior != 0;
            if (node.interior ? !r.get_ids(node.children) : !(r.get(node.first) && r.get(node.count)))
                return truncated();
            if (node.first > UINT32_MAX || node.count > UINT32_MAX)  // as JSON's whole numbers: no wrap-around later
                return Error{"a leaf's first or count is over 2^32 - 1: corrupt"};
        }
    } else if (f.type == AccelType::Kd) {
        if (!r.get_box(f.bounds) || !r.get_count(n, 9)) return truncated();
        f.kd_nodes.resize(n);
        for (size_t i = 0; i < n; ++i) {
            FileKdNode& node = f.kd_nodes[i];
            int8_t axis = 0;
            if (!r.get(axis)) return truncated();
            if (axis > 2) return Error{"node " + std::to_string(i) + ": axis " + std::to_string(axis) + " (0, 1 or 2)"};
            node.axis = axis < 0 ? -1 : axis;
            if (node.is_leaf() ? !r.get_ids(node.triangles)
                               : !(r.get(node.split) && r.get(node.children[0]) && r.get(node.children[1])))
                return truncated();
        }
    } else {
        if (!r.get_box(f.bounds) || !r.get(f.resolution[0]) || !r.get(f.resolution[1]) || !r.get(f.resolution[2]) ||
            !r.get_count(n, 20))
            return truncated();
        f.cells.resize(n);
        for (FileGridCell& c : f.cells)
            if (!r.get(c.cell[0]) || !r.get(c.cell[1]) || !r.get(c.cell[2]) || !r.get_ids(c.triangles))
                return truncated();
    }
    if (!r.at_end()) return Error{"bytes left over after the structure: corrupt"};
    return f;
}

bool looks_like_structure_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string head(4096, '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(size_t(in.gcount()));
    return head.rfind(std::string(kBinaryMagic, sizeof kBinaryMagic), 0) == 0 ||
           head.find(std::string("\"") + kFormatName + "\"") != std::string::npos;
}

Expected<StructureFile> read_structure_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path + ": cannot open: " + std::strerror(errno)};
    std::ostringstream buf;
    buf << in.rdbuf();
    const std::string bytes = std::move(buf).str();
    const bool binary = bytes.size() >= sizeof kBinaryMagic && std::memcmp(bytes.data(), kBinaryMagic, 4) == 0;
    Expected<StructureFile> f = binary ? parse_structure_binary(bytes) : parse_structure_json(bytes);
    if (!f) return Error{path + ": " + f.error()};
    return f;
}

std::optional<Error> write_structure_file(const StructureFile& file, const std::string& path) {
    const bool binary = path.size() >= 4 && path.compare(path.size() - 4, 4, ".avs") == 0;
    std::ofstream out(path, std::ios::binary);
    if (!out) return Error{path + ": cannot write: " + std::strerror(errno)};
    const std::string bytes = binary ? structure_binary(file) : structure_json(file);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) return Error{path + ": writing failed: " + std::strerror(errno)};
    return std::nullopt;
}

// [SECTION] Export of our structures

namespace {

void export_bvh(const Bvh& bvh, StructureFile& f) {
    f.order.assign(bvh.prim_ids.begin(), bvh.prim_ids.end());
    f.bvh_nodes.resize(bvh.nodes.size());
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhNode& n = bvh.nodes[i];
        FileBvhNode& out = f.bvh_nodes[i];
        out.box = n.bounds;
        out.interior = !n.is_leaf();
        if (out.interior) out.children = {n.first, n.first + 1};
        else out.first = n.first, out.count = n.count;
    }
}

/// A wide BVH's boxes as file nodes: a wide node's children are its lanes; a leaf
/// lane becomes a leaf node. Numbered parents before children (breadth first).
template <int W>
void export_wide(const WideBvh<W>& wide, StructureFile& f) {
    f.order.assign(wide.prim_ids.begin(), wide.prim_ids.end());
    if (wide.empty()) return;
    f.bvh_nodes.push_back({wide.root_bounds, wide.root_count == 0, {}, wide.root_first, wide.root_count});
    if (wide.root_count > 0) return;
    std::vector<std::pair<uint32_t, uint32_t>> queue = {{0u, 0u}};  // (file node, wide node)
    for (size_t q = 0; q < queue.size(); ++q) {
        const auto [file_node, w] = queue[q];
        const auto& node = wide.nodes[w];
        for (int i = 0; i < node.child_count; ++i) {
            const auto child = uint32_t(f.bvh_nodes.size());
            f.bvh_nodes[file_node].children.push_back(child);
            FileBvhNode c;
            c.box = node.boxes.get(i);
            c.interior = !node.is_leaf(i);
            if (!c.interior) c.first = node.first[i], c.count = node.count[i];
            else queue.push_back({child, node.first[i]});
            f.bvh_nodes.push_back(std::move(c));
        }
    }
}

void export_kd(const KdTree& kd, StructureFile& f) {
    f.bounds = kd.bounds;
    f.kd_nodes.resize(kd.nodes.size());
    for (size_t i = 0; i < kd.nodes.size(); ++i) {
        const KdNode& n = kd.nodes[i];
        FileKdNode& out = f.kd_nodes[i];
        if (n.is_leaf()) {
            out.triangles.assign(kd.prim_ids.begin() + n.first(), kd.prim_ids.begin() + n.first() + n.count());
        } else {
            out.axis = n.axis();
            out.split = n.split();
            out.children = {n.lower_child(), n.upper_child()};
        }
    }
}

void export_grid(const UniformGrid& g, StructureFile& f) {
    f.bounds = g.bounds;
    f.resolution = {uint32_t(g.res[0]), uint32_t(g.res[1]), uint32_t(g.res[2])};
    for (int k = 0; k < g.res[2]; ++k)
        for (int j = 0; j < g.res[1]; ++j)
            for (int i = 0; i < g.res[0]; ++i) {
                const uint32_t c = g.cell_id(i, j, k);
                if (g.cell_start[c] == g.cell_start[c + 1]) continue;
                f.cells.push_back({{uint32_t(i), uint32_t(j), uint32_t(k)},
                                   {g.tri_ids.begin() + g.cell_start[c], g.tri_ids.begin() + g.cell_start[c + 1]}});
            }
}

}  // namespace

Expected<StructureFile> export_structure(const Accelerator& accel, const Mesh& mesh, MeshReference reference) {
    StructureFile f;
    f.mesh = std::move(reference);
    f.mesh.triangles = mesh.triangle_count();
    f.builder = "accelviz " + accel.name() + " " + accel.config().dump();
    if (const Bvh* bvh = structure_if<Bvh>(accel)) {
        f.type = AccelType::Bvh;
        export_bvh(*bvh, f);
    } else if (const WideBvh<4>* w4 = structure_if<WideBvh<4>>(accel)) {
        f.type = AccelType::Bvh;
        export_wide(*w4, f);
    } else if (const WideBvh<8>* w8 = structure_if<WideBvh<8>>(accel)) {
        f.type = AccelType::Bvh;
        export_wide(*w8, f);
    } else if (const KdTree* kd = structure_if<KdTree>(accel)) {
        f.type = AccelType::Kd;
        export_kd(*kd, f);
    } else if (const UniformGrid* grid = structure_if<UniformGrid>(accel)) {
        f.type = AccelType::Grid;
        export_grid(*grid, f);
    } else {
        return Error{"the exchange format holds a BVH, a KD tree or a grid; " + accel.name() + " has no export"};
    }
    return f;
}

Expected<uint32_t> mesh_crc32(const std::string& source, const Mesh& mesh) {
    Crc32 crc;
    if (source.rfind("builtin:", 0) == 0) {
        for (size_t t = 0; t < mesh.triangle_count(); ++t)
            for (int c = 0; c < 3; ++c) {
                const Vec3 p = mesh.vertex(t, c);
                const float xyz[3] = {p.x, p.y, p.z};
                crc.add(xyz, sizeof xyz);  // x86 and ARM are little-endian, as the format asks
            }
        return crc.value();
    }
    std::ifstream in(source, std::ios::binary);
    if (!in) return Error{source + ": cannot open: " + std::strerror(errno)};
    std::vector<char> buf(1 << 20);
    while (in) {
        in.read(buf.data(), std::streamsize(buf.size()));
        crc.add(buf.data(), size_t(in.gcount()));
    }
    if (in.bad()) return Error{source + ": read error"};
    return crc.value();
}

}  // namespace accelviz

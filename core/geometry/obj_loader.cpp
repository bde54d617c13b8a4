// load_obj: Wavefront OBJ through tinyobjloader, with a validation pass of our own
// in front of it.
//
// Why two passes? tinyobjloader reads numbers leniently (a bad number becomes 0),
// skips faces with fewer than 3 vertices with a warning, and reports a bad index
// at best as "line N" of the whole file after the fact. The lecture tool must say
// exactly what is wrong and where, so scan_obj() walks the text once, looking at
// `v` and `f` lines only, and stops at the first problem with "PATH:LINE: reason".
// Only text that passed the scan reaches tinyobjloader, which then cannot fail on
// anything we care about; its result is checked once more before use, so a
// disagreement between the two parsers is an error message, never a crash.
//
// Both passes work on pieces of the file (whole lines, about 8 MiB each) in
// parallel; the messages and the mesh are those of one pass from the top.
#include <tiny_obj_loader.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <istream>
#include <streambuf>
#include <string_view>
#include <system_error>

#include "core/geometry/scene.h"

namespace accelviz {

namespace {

/// "PATH:LINE: reason", or "PATH: reason" when no line applies (line == 0).
Error located_error(const std::string& path, size_t line, const std::string& reason) {
    if (line == 0) return Error{path + ": " + reason};
    return Error{path + ":" + std::to_string(line) + ": " + reason};
}

/// The whole file as bytes. Errors: missing, a directory, unreadable.
Expected<std::string> read_whole_file(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) return located_error(path, 0, "no such file");
    if (std::filesystem::is_directory(status)) return located_error(path, 0, "is a directory, not an OBJ file");

    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) return located_error(path, 0, std::string("cannot open: ") + std::strerror(errno));
    std::string bytes;
    char buffer[1 << 16];
    size_t got = 0;
    while ((got = std::fread(buffer, 1, sizeof buffer, file)) > 0) bytes.append(buffer, got);
    const bool failed = std::ferror(file) != 0;
    const int read_errno = errno;
    std::fclose(file);
    if (failed) return located_error(path, 0, std::string("cannot read: ") + std::strerror(read_errno));
    return bytes;
}

bool is_blank(char c) { return c == ' ' || c == '\t'; }

/// Splits a line's body into blank-separated words.
/// Calls `word(std::string_view)` for each; stops early if it returns false.
template <class Fn>
bool for_each_word(std::string_view body, Fn&& word) {
    size_t i = 0;
    while (i < body.size()) {
        while (i < body.size() && is_blank(body[i])) ++i;
        if (i == body.size()) break;
        const size_t start = i;
        while (i < body.size() && !is_blank(body[i])) ++i;
        if (!word(body.substr(start, i - start))) return false;
    }
    return true;
}

/// A whole word as an integer (optional sign). False if anything is left over.
bool parse_integer(std::string_view word, long long& out) {
    if (!word.empty() && word[0] == '+') word.remove_prefix(1);
    if (word.empty()) return false;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), out);
    return ec == std::errc() && end == word.data() + word.size();
}

/// A whole word as a number (optional sign, decimal or exponent form; also
/// "inf"/"nan", which the caller rejects as non-finite).
bool parse_number(std::string_view word, double& out) {
    if (!word.empty() && word[0] == '+') word.remove_prefix(1);
    if (word.empty()) return false;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), out);
    if (ec == std::errc::result_out_of_range) {
        out = std::numeric_limits<double>::infinity();  // e.g. 1e999: reported as too large
        return end == word.data() + word.size();
    }
    return ec == std::errc() && end == word.data() + word.size();
}

std::string quoted(std::string_view word) {
    constexpr size_t kMaxShown = 40;  // keep the message on one short line
    std::string out(1, '\'');
    out.append(word.substr(0, kMaxShown));
    out.append(word.size() > kMaxShown ? "...'" : "'");
    return out;
}

/// The reason a `v` line's body is wrong (empty: it is right): x, y and z must be
/// finite floats; an optional w or vertex colour only has to be a number.
std::string check_vertex(std::string_view body) {
    int count = 0;
    std::string bad;
    for_each_word(body, [&](std::string_view word) {
        double value = 0;
        if (!parse_number(word, value)) {
            bad = "bad number " + quoted(word) + " in vertex";
            return false;
        }
        if (count < 3 && !(std::abs(value) <= double(std::numeric_limits<float>::max()))) {
            bad = "non-finite coordinate " + quoted(word) + " (beyond float range or inf/nan)";
            return false;
        }
        if (count < 3 && std::abs(value) > kMaxCoordinate) {
            char limit[32];
            std::snprintf(limit, sizeof limit, "%g", kMaxCoordinate);
            bad = "coordinate " + quoted(word) + " is beyond +-" + limit +
                  ", where the float ray-triangle test overflows (scale the scene down)";
            return false;
        }
        ++count;
        return true;
    });
    if (bad.empty() && count < 3)
        bad = "vertex has " + std::to_string(count) + " coordinate" + (count == 1 ? "" : "s") + ", needs x y z";
    return bad;
}

/// The reason an `f` line's body is wrong (empty: it is right), its words being
/// "v", "v/vt", "v//vn" or "v/vt/vn" with `defined` vertices before the line;
/// `corners` counts them; a negative (relative) index sets `relative_index`. A
/// positive index beyond `defined` (a vertex defined later, perhaps) goes to
/// `forward_index` to be judged at the end of the file.
template <class ForwardIndex>
std::string check_face(std::string_view body, size_t vertices_before, size_t& corners, bool& relative_index,
                       ForwardIndex&& forward_index) {
    const auto defined = static_cast<long long>(vertices_before);
    std::string bad;
    for_each_word(body, [&](std::string_view word) {
        const size_t slash = word.find('/');
        long long index = 0;
        if (!parse_integer(word.substr(0, slash), index)) {
            bad = "bad face index " + quoted(word) + " (want an integer, optionally /vt/vn)";
            return false;
        }
        // Texture and normal indices are ignored, but tinyobjloader rejects 0 or text there.
        for (size_t at = slash; at != std::string_view::npos;) {
            const size_t next = word.find('/', at + 1);
            const std::string_view part = word.substr(at + 1, next == std::string_view::npos ? next : next - at - 1);
            long long other = 0;
            if (!part.empty() && (!parse_integer(part, other) || other == 0)) {
                bad = "bad texture/normal index in " + quoted(word);
                return false;
            }
            at = next;
        }
        if (index == 0) {
            bad = "face index 0 is invalid (OBJ indices start at 1)";
            return false;
        }
        if (index < 0) relative_index = true;
        if (index < 0 && defined + index < 0) {
            bad = "face index " + std::to_string(index) + " out of range (only " + std::to_string(defined) +
                  " vertices before this line)";
            return false;
        }
        if (index > defined) forward_index(index);
        ++corners;
        return true;
    });
    if (bad.empty() && corners < 3)
        bad = "face has " + std::to_string(corners) + (corners == 1 ? " vertex" : " vertices") + ", needs at least 3";
    return bad;
}

/// Calls `fn(std::string_view line)` for each line of text[begin, end). Lines end at
/// "\n", "\r\n" or a lone "\r", as in tinyobjloader, so both count lines (and so
/// vertices, on which relative indices depend) alike.
template <class Fn>
void for_each_line(const std::string& text, size_t begin, size_t end, Fn&& fn) {
    size_t pos = begin;
    while (pos < end) {
        size_t line_end = pos;
        while (line_end < end && text[line_end] != '\n' && text[line_end] != '\r') ++line_end;
        fn(std::string_view(text).substr(pos, line_end - pos));
        pos = line_end;
        if (pos < end) pos += (text[pos] == '\r' && pos + 1 < end && text[pos + 1] == '\n') ? 2 : 1;
    }
}

/// What a line is, for the scan: a vertex (`v`), a face (`f`), a line that looks like
/// one of them and is not ("v1 2 3", "f1 2 3": no OBJ statement starts so; read as one
/// it would silently shift every later vertex index), or anything else (vn, vt, g, o,
/// usemtl, comments, blank lines...). Leading blanks are removed from `line`.
enum class ObjLine { Other, Vertex, Face, Malformed };

ObjLine classify(std::string_view& line) {
    size_t start = 0;
    while (start < line.size() && is_blank(line[start])) ++start;
    line.remove_prefix(start);
    if (line.empty() || (line[0] != 'v' && line[0] != 'f')) return ObjLine::Other;
    if (line.size() == 1 || is_blank(line[1])) return line[0] == 'v' ? ObjLine::Vertex : ObjLine::Face;
    if (std::isdigit(static_cast<unsigned char>(line[1])) || line[1] == '-' || line[1] == '+' || line[1] == '.')
        return ObjLine::Malformed;
    return ObjLine::Other;
}

/// A piece of the file made of whole lines, text[begin, end). The file is scanned and
/// parsed piece by piece in parallel: a first pass counts each piece's lines and
/// vertices, so that each piece then knows its first line number and how many
/// vertices come before it (what relative and forward indices are judged by).
struct ObjPiece {
    size_t begin = 0, end = 0;
    size_t lines = 0, vertices = 0;                 ///< in this piece (first pass)
    size_t lines_before = 0, vertices_before = 0;   ///< in the pieces before it
    size_t triangles = 0, triangles_before = 0;     ///< after fan triangulation (the scan)

    // The scan's findings.
    struct ForwardIndex {
        size_t line;
        long long index;
    };
    /// A positive index may point forward (to a vertex defined later in the file),
    /// so it can only be judged at the end. Remembered: each index larger than every
    /// vertex count so far and every index remembered before in this piece. The
    /// earliest line with an index beyond the final count is then the first such
    /// entry of the file (each piece's list is increasing), which keeps the lists short.
    std::vector<ForwardIndex> forward;
    size_t error_line = 0;  ///< the piece's first error (0: none)
    std::string error_reason;
    bool relative_index = false;  ///< a negative (relative) vertex index
};

/// Pieces of about kPieceBytes ending at a line feed, so none splits a line. Their
/// number depends on the file alone (not on the threads), and so does the mesh.
std::vector<ObjPiece> split_into_pieces(const std::string& text) {
    constexpr size_t kPieceBytes = size_t(8) << 20;
    std::vector<ObjPiece> pieces;
    size_t begin = 0;
    while (begin < text.size()) {
        size_t end = text.size();
        if (text.size() - begin > 2 * kPieceBytes) {
            const size_t feed = text.find('\n', begin + kPieceBytes);
            if (feed != std::string::npos) end = feed + 1;
        }
        pieces.emplace_back();
        pieces.back().begin = begin;
        pieces.back().end = end;
        begin = end;
    }
    return pieces;
}

/// The validation pass over one piece's `v` and `f` lines. It also blanks out a
/// comment at the end of a `v` or `f` line ("f 1 2 3 # top"), which tinyobjloader
/// would read as one more index.
void scan_piece(std::string& text, ObjPiece& piece) {
    size_t line_number = piece.lines_before;
    size_t vertex_count = piece.vertices_before;
    long long forward_max = 0;
    for_each_line(text, piece.begin, piece.end, [&](std::string_view line) {
        ++line_number;
        const ObjLine kind = classify(line);
        if (kind == ObjLine::Malformed) {
            if (piece.error_line == 0) {
                piece.error_line = line_number;
                piece.error_reason = std::string("'") + line[0] + "' must be followed by a blank: " +
                                     quoted(line.substr(0, line.find_first_of(" \t"))) + " is not a statement";
            }
            return;
        }
        if (kind == ObjLine::Other) return;
        if (const size_t hash = line.find('#'); hash != std::string_view::npos) {
            const size_t from = size_t(line.data() - text.data()) + hash;
            std::fill(text.begin() + std::ptrdiff_t(from), text.begin() + std::ptrdiff_t(from + line.size() - hash), ' ');
            line = line.substr(0, hash);
        }
        const std::string_view body = line.substr(1);
        if (kind == ObjLine::Vertex) {
            if (piece.error_line == 0) {
                if (std::string bad = check_vertex(body); !bad.empty()) {
                    piece.error_line = line_number;
                    piece.error_reason = bad;
                }
            }
            ++vertex_count;
            return;
        }
        if (piece.error_line != 0) return;  // after an error only vertices are counted
        size_t corners = 0;
        std::string bad = check_face(body, vertex_count, corners, piece.relative_index, [&](long long index) {
            if (index > forward_max) {
                piece.forward.push_back({line_number, index});
                forward_max = index;
            }
        });
        if (!bad.empty()) {
            // Scanning goes on, counting vertices only: a forward index on an earlier
            // line can only be judged with the final count, and it comes first.
            piece.error_line = line_number;
            piece.error_reason = bad;
            return;
        }
        piece.triangles += corners - 2;
    });
}

/// What the scan found in a file that passed it.
struct ObjScan {
    size_t vertex_count = 0;    ///< `v` lines
    size_t triangle_count = 0;  ///< after fan triangulation
    bool relative_index = false;
    std::vector<ObjPiece> pieces;
};

/// The validation pass over `v` and `f` lines, piece by piece in parallel. It stops
/// at the file's first problem, "PATH:LINE: reason", exactly as one pass from the
/// top would.
Expected<ObjScan> scan_obj(std::string& text, const std::string& path, WorkProgress* progress) {
    ObjScan scan;
    scan.pieces = split_into_pieces(text);
    std::vector<ObjPiece>& pieces = scan.pieces;
    tbb::parallel_for(size_t(0), pieces.size(), [&](size_t k) {
        ObjPiece& piece = pieces[k];
        if (cancelled(progress)) return;
        advance(progress, piece.end - piece.begin);
        for_each_line(text, piece.begin, piece.end, [&](std::string_view line) {
            ++piece.lines;
            if (classify(line) == ObjLine::Vertex) ++piece.vertices;
        });
    });
    for (size_t k = 1; k < pieces.size(); ++k) {
        pieces[k].lines_before = pieces[k - 1].lines_before + pieces[k - 1].lines;
        pieces[k].vertices_before = pieces[k - 1].vertices_before + pieces[k - 1].vertices;
    }
    tbb::parallel_for(size_t(0), pieces.size(), [&](size_t k) {
        if (cancelled(progress)) return;
        advance(progress, pieces[k].end - pieces[k].begin);
        scan_piece(text, pieces[k]);
    });
    if (cancelled(progress)) return WorkProgress::cancelled_error();

    size_t error_line = 0;
    std::string error_reason;
    for (ObjPiece& piece : pieces) {
        scan.vertex_count += piece.vertices;
        piece.triangles_before = scan.triangle_count;
        scan.triangle_count += piece.triangles;
        scan.relative_index = scan.relative_index || piece.relative_index;
        if (piece.error_line != 0 && error_line == 0) {
            error_line = piece.error_line;
            error_reason = piece.error_reason;
        }
    }
    const auto total = static_cast<long long>(scan.vertex_count);
    for (const ObjPiece& piece : pieces) {
        for (const ObjPiece::ForwardIndex& f : piece.forward) {
            if (f.index <= total) continue;
            if (error_line == 0 || f.line < error_line)
                return located_error(path, f.line,
                                     "face index " + std::to_string(f.index) + " out of range (file has " +
                                         std::to_string(total) + " vertices)");
            return located_error(path, error_line, error_reason);
        }
    }
    if (error_line != 0) return located_error(path, error_line, error_reason);
    return scan;
}

/// The first line of tinyobjloader's message, for an error we did not foresee.
std::string first_line(const std::string& message) {
    const std::string line = message.substr(0, message.find('\n'));
    return line.empty() ? "tinyobjloader could not parse the file" : "tinyobjloader: " + line;
}

/// A read-only stream over text[begin, end): tinyobjloader reads a piece of the file
/// where it lies, without a copy.
class PieceBuffer : public std::streambuf {
public:
    PieceBuffer(const std::string& text, size_t begin, size_t end) {
        char* data = const_cast<char*>(text.data());  // only read: a streambuf's get area is char*
        setg(data + begin, data + begin, data + end);
    }
};

/// tinyobjloader's reading of one piece (which passed the scan): its vertices go to
/// mesh.positions from piece.vertices_before on, its faces, fan-triangulated, to
/// mesh.indices from piece.triangles_before on. Returns what went wrong (empty: nothing).
///
/// No material reader: mtllib/usemtl lines are ignored. triangulate=false: we fan-
/// triangulate, because tinyobjloader's own triangulation splits quads along the
/// shorter diagonal and clips ears of larger polygons, which is not the documented
/// fan and can drop triangles of a degenerate polygon. A positive index comes back
/// as index - 1 whatever the piece; a negative one relative to the piece's own
/// vertices, which is why a file with negative indices is read as one piece.
std::string parse_piece(const std::string& text, const ObjPiece& piece, size_t vertex_total, Mesh& mesh) {
    PieceBuffer buffer(text, piece.begin, piece.end);
    std::istream stream(&buffer);
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::string warn, err;
    if (!tinyobj::LoadObj(&attrib, &shapes, /*materials=*/nullptr, &warn, &err, &stream,
                          /*readMatFn=*/nullptr, /*triangulate=*/false, /*default_vcols_fallback=*/false))
        return first_line(err);

    const size_t vertex_count = attrib.vertices.size() / 3;
    if (vertex_count != piece.vertices)
        return "tinyobjloader read " + std::to_string(vertex_count) + " vertices, expected " +
               std::to_string(piece.vertices);
    for (size_t i = 0; i < vertex_count; ++i)
        mesh.positions[piece.vertices_before + i] = {float(attrib.vertices[3 * i]), float(attrib.vertices[3 * i + 1]),
                                                     float(attrib.vertices[3 * i + 2])};

    // Fan triangulation: polygon (c0, c1, ..., c(k-1)) → (c0, ci, ci+1) for i = 1 .. k-2.
    size_t triangle = piece.triangles_before;
    const size_t triangle_end = piece.triangles_before + piece.triangles;
    for (const tinyobj::shape_t& shape : shapes) {
        const auto& corners = shape.mesh.indices;
        size_t first = 0;
        for (const unsigned int face_size : shape.mesh.num_face_vertices) {
            if (first + face_size > corners.size()) return "tinyobjloader returned a truncated face list";
            auto corner = [&](size_t k) -> long long { return corners[first + k].vertex_index; };
            for (size_t k = 0; k < face_size; ++k)
                if (corner(k) < 0 || corner(k) >= static_cast<long long>(vertex_total))
                    return "face index out of range after loading";
            for (size_t k = 1; k + 1 < face_size; ++k) {
                if (triangle == triangle_end) return "tinyobjloader returned more triangles than the file has";
                mesh.indices[triangle++] = {uint32_t(corner(0)), uint32_t(corner(k)), uint32_t(corner(k + 1))};
            }
            first += face_size;
        }
    }
    if (triangle != triangle_end)
        return "tinyobjloader returned " + std::to_string(triangle - piece.triangles_before) + " triangles, expected " +
               std::to_string(piece.triangles);
    return {};
}

/// `progress`: three passes over the bytes (count, check, parse), a piece at a time.
Expected<Mesh> parse_obj_unguarded(std::string bytes, const std::string& path, WorkProgress* progress) {
    // A UTF-8 byte-order mark (Windows tools write one) is not part of the first line.
    if (bytes.starts_with("\xEF\xBB\xBF")) bytes.erase(0, 3);

    start_stage(progress, 3 * uint64_t(bytes.size()));
    auto scan = scan_obj(bytes, path, progress);
    if (!scan) return Error{scan.error()};
    if (scan->triangle_count == 0) {
        if (bytes.find_first_not_of(" \t\r\n") == std::string::npos) return located_error(path, 0, "empty file (no triangles)");
        return located_error(path, 0, "no triangles (" + std::to_string(scan->vertex_count) + " vertices, no faces)");
    }
    if (scan->vertex_count > std::numeric_limits<uint32_t>::max())
        return located_error(path, 0, "too many vertices for 32-bit indices (" + std::to_string(scan->vertex_count) + ")");

    std::vector<ObjPiece> pieces = std::move(scan->pieces);
    if (scan->relative_index) {  // one piece: see parse_piece
        ObjPiece whole;
        whole.end = bytes.size();
        whole.vertices = scan->vertex_count;
        whole.triangles = scan->triangle_count;
        pieces.assign(1, whole);
    }
    Mesh mesh;
    mesh.name = path;
    mesh.positions.resize(scan->vertex_count);
    mesh.indices.resize(scan->triangle_count);
    std::vector<std::string> problems(pieces.size());
    tbb::parallel_for(size_t(0), pieces.size(), [&](size_t k) {
        if (cancelled(progress)) return;
        problems[k] = parse_piece(bytes, pieces[k], scan->vertex_count, mesh);
        advance(progress, pieces[k].end - pieces[k].begin);
    });
    if (cancelled(progress)) return WorkProgress::cancelled_error();
    for (const std::string& problem : problems)
        if (!problem.empty()) return located_error(path, 0, problem);
    return mesh;
}

}  // namespace

/// Runs `load` with nothing escaping to the caller: a huge file can still run out of memory.
template <class Load>
Expected<Mesh> guarded(const std::string& path, Load&& load) {
    try {
        return load();
    } catch (const std::exception& e) {
        return located_error(path, 0, std::string("cannot load: ") + e.what());
    } catch (...) {
        return located_error(path, 0, "cannot load: unknown error");
    }
}

Expected<Mesh> load_obj(const std::string& path, WorkProgress* progress) {
    return guarded(path, [&]() -> Expected<Mesh> {
        auto bytes = read_whole_file(path);
        if (!bytes) return Error{bytes.error()};
        if (cancelled(progress)) return WorkProgress::cancelled_error();
        return parse_obj_unguarded(std::move(*bytes), path, progress);
    });
}

Expected<std::vector<ObjObject>> obj_objects(const std::string& path) {
    auto bytes = read_whole_file(path);
    if (!bytes) return Error{bytes.error()};
    if (bytes->starts_with("\xEF\xBB\xBF")) bytes->erase(0, 3);  // a byte-order mark, as the loader skips it
    std::vector<ObjObject> objects(1);
    size_t triangles = 0;
    for_each_line(*bytes, 0, bytes->size(), [&](std::string_view line) {
        if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        const ObjLine kind = classify(line);  // (leading blanks removed)
        if (kind == ObjLine::Face) {
            // As the scan counts them: a face of k corners makes k - 2 triangles (a fan).
            size_t corners = 0;
            for (size_t i = 1; i < line.size();) {
                while (i < line.size() && is_blank(line[i])) ++i;
                if (i >= line.size()) break;
                ++corners;
                while (i < line.size() && !is_blank(line[i])) ++i;
            }
            if (corners >= 3) {
                triangles += corners - 2;
                objects.back().triangle_count += corners - 2;
            }
            return;
        }
        if (kind != ObjLine::Other || line.size() < 1 || (line[0] != 'o' && line[0] != 'g') ||
            (line.size() > 1 && !is_blank(line[1])))
            return;
        std::string_view name = line.substr(1);
        while (!name.empty() && is_blank(name.front())) name.remove_prefix(1);
        while (!name.empty() && is_blank(name.back())) name.remove_suffix(1);
        if (objects.back().triangle_count > 0) objects.push_back({std::string(), triangles, 0});
        objects.back().name = std::string(name);
    });
    return objects;
}

Expected<Mesh> parse_obj(std::string text, const std::string& name) {
    return guarded(name, [&]() -> Expected<Mesh> { return parse_obj_unguarded(std::move(text), name, nullptr); });
}

}  // namespace accelviz

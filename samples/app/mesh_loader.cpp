// --mesh FILE: OBJ / PLY (and whatever else assimp reads) dropped on a floor with a default area
// light and a camera framing it.
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <glm/glm.hpp>

#include <cmath>
#include <filesystem>

#include "scene.hpp"

namespace sk {

bool load_mesh_scene(const std::string& path, Scene& out, std::string& why) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        why = "mesh file not found: " + path;
        return false;
    }
    Assimp::Importer importer;
    const aiScene* as = importer.ReadFile(
        path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                  aiProcess_PreTransformVertices | aiProcess_FindInvalidData);
    if (as == nullptr || as->mNumMeshes == 0) {
        why = "cannot read mesh " + path + ": " + (as ? "no triangle meshes in file" : importer.GetErrorString());
        return false;
    }
    Mesh m;
    m.name = std::filesystem::path(path).filename().string();
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
    if (m.indices.empty()) {
        why = "mesh " + path + " has no triangles";
        return false;
    }
    // scale to a 2-unit footprint, rest it on the floor at the origin
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const auto& p : m.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const glm::vec3 ext = hi - lo;
    const float footprint = std::max(std::max(ext.x, ext.z), ext.y);
    if (!(footprint > 0.f) || !std::isfinite(footprint)) {
        why = "mesh " + path + " is degenerate (zero extent)";
        return false;
    }
    const float s = 2.f / footprint;
    const glm::vec3 shift(-(lo.x + hi.x) * 0.5f, -lo.y, -(lo.z + hi.z) * 0.5f);
    for (auto& p : m.positions) p = (p + shift) * s;
    out = Scene{};
    out.name = "mesh:" + m.name;
    out.description = "user mesh " + m.name + " (" + std::to_string(m.indices.size() / 3) + " triangles) on a floor";
    out.meshes.push_back(make_plane("floor", {0.f, 0.f, 0.f}, 4.f, 4.f));
    out.meshes.back().caster = false;
    const float height = ext.y * s;
    out.meshes.push_back(std::move(m));
    out.light.type = LightType::Rect;
    out.light.position = {1.2f, 2.f + 2.f * height, 1.0f};
    out.light.direction = glm::normalize(glm::vec3(0.f, height * 0.5f, 0.f) - out.light.position);
    out.light.size = 0.5f;
    out.light.spot_half_angle = 0.9f;
    out.camera.eye = {0.f, 1.5f + height, 4.5f};
    out.camera.target = {0.f, 0.4f * height, 0.f};
    return true;
}

}  // namespace sk

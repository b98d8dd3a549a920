// Internal helpers shared by the technique drivers (samples/common/drivers_*.cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "gl_harness.hpp"
#include "techniques.hpp"

namespace sk {

// Light uniforms read by visibility_fragment_shader()'s common light rules.
void set_light_uniforms(GLuint prog, const Light& L);

// Position-only depth pass (u_light_view_proj).
const char* depth_only_vs();
const char* depth_only_fs();

// Full-screen pass over the G-buffer writing V into an R32F target (units 0/1 = G-buffer).
struct VisibilityPass {
    skgl::Target target;
    GLuint vao = 0;
    VisibilityPass() = default;
    VisibilityPass(const VisibilityPass&) = delete;
    VisibilityPass& operator=(const VisibilityPass&) = delete;
    ~VisibilityPass();
    bool init(int w, int h, std::string& why);
    void draw(GLuint prog, const SceneGpu& gpu);
};

// Draws the caster meshes (all, or only the listed mesh indices).
void draw_casters(const SceneGpu& gpu, const std::vector<std::uint32_t>* only = nullptr);
std::size_t caster_count(const SceneGpu& gpu);
void mesh_bounds(const Mesh& m, glm::vec3& lo, glm::vec3& hi);

// Registration of the drivers that live in their own files (common/drivers_<family>.cpp).
void add_warp_techniques(std::vector<std::unique_ptr<Technique>>& out);      // drivers_warp.cpp
void add_soft_techniques(std::vector<std::unique_ptr<Technique>>& out);      // drivers_soft.cpp
void add_volume_techniques(std::vector<std::unique_ptr<Technique>>& out);    // drivers_volume.cpp
void add_smoothie_techniques(std::vector<std::unique_ptr<Technique>>& out);  // drivers_smoothie.cpp
void add_wedge_techniques(std::vector<std::unique_ptr<Technique>>& out);     // drivers_wedge.cpp
void add_omni_techniques(std::vector<std::unique_ptr<Technique>>& out);      // drivers_omni.cpp
void add_silmap_techniques(std::vector<std::unique_ptr<Technique>>& out);    // drivers_silmap.cpp
void add_linear_techniques(std::vector<std::unique_ptr<Technique>>& out);    // drivers_linear.cpp

}  // namespace sk

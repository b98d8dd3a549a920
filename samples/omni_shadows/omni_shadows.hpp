// samples/omni_shadows/omni_shadows.hpp - a point light's shadows from one cube map (omni_shadow.hpp):
// six 90-degree faces storing the linear distance to the light, the casters culled per face, the
// receiver-side bias of omni_distance_bias. What the sample shows and the report measures. The
// dual-paraboloid map of the same header is samples/dual_paraboloid/.
//
// A sample folder is what a user copies (the same shape in every samples/<technique>/):
//   omni_shadows.hpp  the settings (what the panel edits, named once in bind_settings()) and the class
//   omni_shadows.cpp  the technique, top to bottom in the order it runs: init (once per scene),
//                     update (CPU, every frame), render (the GPU passes, each with its GL state)
//   main.cpp          the calls: the app shell (samples/app) does the window, the camera G-buffer,
//                     the panel, the timing and the picture
// It uses only shadowkit/omni_shadow.hpp, glsl/omni_shadow.glsl and the app shell's G-buffer
// (app/gbuffer.hpp) and GL helpers (app/gl.hpp). shadowkit-report wraps this same class
// (samples/report/techniques/omni.cpp).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "app.hpp"
#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

struct OmniShadowSettings {
    int size = 512;        ///< texels per side of each face
    bool culling = true;   ///< draw a caster only into the faces its box meets (omni_cull_face_lists)
    /// hardware: one hardware 2x2 compare (samplerCubeShadow, GL_LINEAR); manual: the nearest texel
    /// read and compared in the shader (samplerCube); pcf: 3x3 hardware compares, across face seams.
    enum class Lookup { Hardware, Manual, Pcf };
    Lookup lookup = Lookup::Hardware;
};

/// The settings by name, once: --param, the panel's widgets and the report's sweeps use these.
inline void bind_settings(app::Params& p, OmniShadowSettings& s) {
    using L = OmniShadowSettings::Lookup;
    p.choice("size", &s.size, {{"128", 128}, {"256", 256}, {"512", 512}, {"1024", 1024}, {"2048", 2048}});
    p.toggle("culling", &s.culling);
    p.choice("lookup", &s.lookup, {{"hardware", L::Hardware}, {"manual", L::Manual}, {"pcf", L::Pcf}});
}

class OmniShadows {
public:
    OmniShadows() = default;
    OmniShadows(const OmniShadows&) = delete;
    OmniShadows& operator=(const OmniShadows&) = delete;
    ~OmniShadows() { release(); }

    /// The casters' boxes, the programs and the V target.
    bool init(const app::View& v, std::string& why);
    /// CPU, every frame: the stored distance's range, the six faces' matrices, the casters of each face.
    void update(const app::View& v, const OmniShadowSettings& s);
    /// GPU, every frame: the distances into the six faces, then V at the G-buffer's points.
    void render(const app::View& v, const OmniShadowSettings& s);
    /// R32F V at the G-buffer's pixels.
    GLuint visibility() const { return pass_.texture(); }
    /// Why update() found no cube (a header's status: the sun is InvalidLight), "" while all is well.
    /// V is 1 (lit) meanwhile.
    const std::string& error() const { return error_; }

    /// Debug view: the six faces' stored distances, +x -x +y in the bottom row, -y +z -z above.
    app::DebugImage debug_faces();

    /// The meshes drawn into face f this frame (indices into Scene::meshes), for the report's counters.
    const std::vector<std::uint32_t>& face_meshes(int f) const { return face_meshes_[f]; }
    std::size_t caster_count() const { return mesh_of_.size(); }
    int size() const { return size_; }  ///< texels per side of a face as rendered last

private:
    void make_cube(int size);
    void release();
    std::vector<float> boxes_;            // the casters' boxes, 6 floats each
    std::vector<std::uint32_t> mesh_of_;  // box -> mesh index
    std::vector<std::uint32_t> lists_;    // omni_cull_face_lists' output
    std::vector<std::uint32_t> face_meshes_[6];
    std::string error_;
    // this frame
    glm::mat4 face_vp_[6];
    float range_ = 0.f;                   // the stored distance's range: the farthest scene corner (+1%)
    // GL
    int size_ = 0;
    GLuint cube_ = 0, fbo_[6] = {0, 0, 0, 0, 0, 0}, nearest_ = 0;
    GLuint depth_prog_ = 0, vis_prog_ = 0, atlas_prog_ = 0, faces_view_ = 0, vao_ = 0;
    app::VisibilityPass pass_;
    skgl::Target atlas_;                  // the faces' debug view (R32F)
};

// samples/app/app.hpp - the app shell every sample's main() uses: small and boring on purpose.
//
// What a sample folder looks like (samples/shadow_volumes/ is the template):
//   <technique>.hpp/.cpp  the technique: `struct <T>Settings` (what the panel edits), `class <T>` with
//                         init(view, why) once per scene, update(view, settings) on the CPU and
//                         render(view, settings) on the GPU every frame, visibility() (R32F V at the
//                         G-buffer's pixels) and its debug views; `bind_settings(Params&, Settings&)` names
//                         the settings once for --param, the panel and the report.
//   main.cpp              the calls, visible: the App, the bindings, the frame loop.
//
// The App does the rest: options, a GLFW window with a Dear ImGui panel (the settings, the debug views,
// the light, the CPU/GPU time of each pass) or EGL headless, the orbit camera, the built-in scenes and
// mesh files, the camera G-buffer (gbuffer.hpp), the composite of V, PNG output and frame timing.
//
//   sample [--scene NAME | --mesh FILE] [--headless [OUT.png]] [--out OUT.png] [--frames N] [--size WxH]
//          [--param name=value]... [--view NAME] [--help]
// Unknown options, scenes, parameters, values and views are errors that list the valid ones (exit 2).
// Headless (EGL surfaceless, no display): N frames (default 1) with the light turning 360/N degrees a
// frame about the scene's vertical axis, the last one written as PNG (default shot.png), the median
// time of every pass printed; exit 77 without a GL context (1 when SHADOWKIT_REQUIRE_GL is set).
// Window keys: drag to orbit, arrows and PageUp/PageDown move the light, V cycles the debug views,
// N/P the next/previous scene, Esc quits; `--frames N` closes the window after N frames.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "gbuffer.hpp"
#include "gl.hpp"
#include "params.hpp"

namespace app {

/// A debug view a technique offers: a texture and how to show it.
struct DebugImage {
    enum class Show {
        Value,    ///< the red channel in grey, stretched over its finite range
        Depth,    ///< a depth texture (its compare mode bypassed) in grey, stretched over the depths below 1
        Stencil,  ///< the stencil of a DEPTH*_STENCIL8 texture: grey = 64 x the count, saturated
        Overlay   ///< RGBA drawn over the shaded picture (alpha 0: the picture shows through)
    };
    GLuint texture = 0;  ///< a 2D texture; 0: nothing to show for this scene or light (the panel says so)
    Show show = Show::Value;
};

class App {
public:
    explicit App(std::string title);
    ~App();
    App(const App&) = delete;
    App& operator=(const App&) = delete;

    /// The technique's settings by name (bind before start()): --param, the panel's widgets.
    Params& params() { return params_; }
    /// A debug view, shown by name (bind before start()): --view NAME, the V key, the panel.
    void debug_view(const std::string& name, std::function<DebugImage()> image);
    /// The scene the sample starts on when --scene is not given (before start(); default "contact").
    void default_scene(const std::string& name);
    /// A scene of the sample's own (before start()): offered after the built-in ones by --scene, N/P
    /// and the panel (samples/prt: its tessellated scene).
    void add_scene(sk::Scene scene);

    /// Options, the window (GLFW + Dear ImGui) or the EGL context, the scene and its G-buffer. false:
    /// stop and return exit_code() (0 after --help, 2 for a bad option, 77 without GL, 1 otherwise).
    bool start(int argc, char** argv);
    int exit_code() const { return exit_code_; }
    /// Prints "<program>: <why>" and returns 1, the exit code of a technique that failed.
    int fail(const std::string& why);

    /// Input, camera, light, and the G-buffer when the camera, the scene or the size changed. false
    /// when the sample ends (window closed, Esc, the last headless frame written, an error).
    bool next_frame();
    /// True on the first frame and whenever the scene or the G-buffer's size changed: init() again.
    bool scene_changed() const { return scene_changed_; }
    /// The scene, its GPU meshes and G-buffer, the camera: what init / update / render take.
    const View& view() const { return view_; }

    /// Runs fn and records its CPU time (steady clock) as the pass `name`.
    void cpu(const char* name, const std::function<void()>& fn);
    /// Runs fn and records its GPU time as the pass `name`: a GL timer query on a GPU, glFinish and
    /// the steady clock on llvmpipe (where the GPU work runs on the CPU).
    void gpu(const char* name, const std::function<void()>& fn);
    /// The technique's own extra widgets (Dear ImGui calls), drawn in the panel; never called without ImGui.
    void panel(std::function<void()> widgets);
    /// Shows V: the composite albedo * (ambient + V N.L) or the chosen debug view, and the panel
    /// (window); headless, the PNG of the last frame.
    void present(GLuint visibility);
    /// present() for a technique that shades the picture itself (samples/prt): its RGBA color
    /// texture at the G-buffer's size instead of the composite of V.
    void present_color(GLuint picture);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    Params params_;
    View view_;
    bool scene_changed_ = false;
    int exit_code_ = 0;
};

}  // namespace app

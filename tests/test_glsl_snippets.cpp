// Every glsl/*.glsl snippet compiles with glslang (library API, in process) for every GLSL version
// and stage its header comment declares, as a complete shader: "#version V core" + snippet +
// the driver tests/glsl/<snippet>.<stage>.glsl whose main() calls the snippet's functions.
// A snippet without a driver for a declared stage fails; a broken fixture must fail.
#include <doctest/doctest.h>

#include <shadowkit/poisson_disk.hpp>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct GlslangProcess {
    GlslangProcess() { glslang::InitializeProcess(); }
    ~GlslangProcess() { glslang::FinalizeProcess(); }
};
const GlslangProcess g_process;

std::string read_file(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

std::vector<std::string> split_list(const std::string& s) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : s) {
        if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
            if (!cur.empty()) out.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    if (!cur.empty()) out.push_back(cur);
    return out;
}

// Reads "// versions: ..." and "// stages: ..." from the snippet's leading comment block.
bool parse_header(const std::string& src, std::vector<std::string>& versions, std::vector<std::string>& stages) {
    std::istringstream in(src);
    std::string line;
    while (std::getline(in, line)) {
        const auto pos = line.find_first_not_of(" \t");
        if (pos == std::string::npos) continue;
        if (line.compare(pos, 2, "//") != 0) break;  // end of the header comment
        const std::string body = line.substr(pos + 2);
        const auto colon = body.find(':');
        if (colon == std::string::npos) continue;
        std::string key = body.substr(0, colon);
        key.erase(std::remove_if(key.begin(), key.end(), [](unsigned char c) { return std::isspace(c); }), key.end());
        if (key == "versions") versions = split_list(body.substr(colon + 1));
        if (key == "stages") stages = split_list(body.substr(colon + 1));
    }
    return !versions.empty() && !stages.empty();
}

bool stage_of(const std::string& name, EShLanguage& lang) {
    static const std::map<std::string, EShLanguage> m = {{"vertex", EShLangVertex},
                                                         {"fragment", EShLangFragment},
                                                         {"geometry", EShLangGeometry},
                                                         {"compute", EShLangCompute}};
    auto it = m.find(name);
    if (it == m.end()) return false;
    lang = it->second;
    return true;
}

// Compiles and links one stage; returns "" on success, the info log otherwise.
std::string compile(const std::string& source, EShLanguage lang, int version) {
    glslang::TShader shader(lang);
    const char* text = source.c_str();
    shader.setStrings(&text, 1);
    const auto messages = static_cast<EShMessages>(EShMsgDefault);
    if (!shader.parse(GetDefaultResources(), version, ECoreProfile, false, false, messages))
        return std::string("compile: ") + shader.getInfoLog();
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) return std::string("link: ") + program.getInfoLog();
    return {};
}

struct Failure {
    std::string what;
};

// Checks one snippet against its drivers; appends failures.
void check_snippet(const fs::path& snippet, const fs::path& driver_dir, std::vector<Failure>& failures,
                   int& compiled) {
    const std::string src = read_file(snippet);
    const std::string stem = snippet.stem().string();
    std::vector<std::string> versions, stages;
    if (!parse_header(src, versions, stages)) {
        failures.push_back({stem + ": header comment lacks '// versions:' or '// stages:'"});
        return;
    }
    if (src.find("#version") != std::string::npos) {
        failures.push_back({stem + ": snippets must not contain #version (the user's shader has one)"});
    }
    for (const auto& st : stages) {
        EShLanguage lang{};
        if (!stage_of(st, lang)) {
            failures.push_back({stem + ": unknown stage '" + st + "'"});
            continue;
        }
        const fs::path driver = driver_dir / (stem + "." + st + ".glsl");
        if (!fs::exists(driver)) {
            failures.push_back({stem + ": missing driver " + driver.string()});
            continue;
        }
        const std::string drv = read_file(driver);
        for (const auto& v : versions) {
            const int ver = std::atoi(v.c_str());
            const std::string full = "#version " + v + " core\n#line 1\n" + src + "\n#line 1\n" + drv;
            const std::string err = compile(full, lang, ver);
            if (!err.empty())
                failures.push_back({stem + " (" + st + ", GLSL " + v + "): " + err});
            else
                ++compiled;
        }
    }
}

}  // namespace

TEST_CASE("every glsl/ snippet compiles with glslang for its declared versions and stages") {
    std::vector<Failure> failures;
    int compiled = 0, snippets = 0;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(SHADOWKIT_GLSL_DIR))
        if (e.path().extension() == ".glsl") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        ++snippets;
        check_snippet(f, SHADOWKIT_GLSL_DRIVER_DIR, failures, compiled);
    }
    for (const auto& f : failures) FAIL_CHECK(f.what);
    MESSAGE(snippets << " snippets, " << compiled << " (snippet, stage, version) compilations");
    CHECK(snippets > 0);
    CHECK(compiled >= snippets);
}

TEST_CASE("a broken snippet fails the compile check (the check can fail)") {
    std::vector<Failure> failures;
    int compiled = 0;
    check_snippet(fs::path(SHADOWKIT_GLSL_FIXTURE_DIR) / "broken.glsl", SHADOWKIT_GLSL_FIXTURE_DIR, failures, compiled);
    CHECK(compiled == 0);
    REQUIRE(failures.size() == 1);
    CHECK(failures[0].what.find("compile") != std::string::npos);
}

TEST_CASE("a snippet whose driver is missing fails") {
    std::vector<Failure> failures;
    int compiled = 0;
    check_snippet(fs::path(SHADOWKIT_GLSL_FIXTURE_DIR) / "no_driver.glsl", SHADOWKIT_GLSL_FIXTURE_DIR, failures,
                  compiled);
    REQUIRE(failures.size() == 1);
    CHECK(failures[0].what.find("missing driver") != std::string::npos);
}

TEST_CASE("the same snippet and driver compile when correct (fixture sanity)") {
    std::vector<Failure> failures;
    int compiled = 0;
    check_snippet(fs::path(SHADOWKIT_GLSL_FIXTURE_DIR) / "good.glsl", SHADOWKIT_GLSL_FIXTURE_DIR, failures, compiled);
    CHECK(failures.empty());
    CHECK(compiled == 2);  // versions 330 and 450
}

// ---------------------------------------------------------------------------------- Poisson arrays
// Issue 13 item 5: an array from shadowkit::poisson_to_glsl pasted before pcf.glsl and pcss.glsl
// (the README's name SK_POISSON_DISK) redeclared the snippets' own array and did not compile. The
// built-in disk is sk_poisson_disk64 now; a generated array of any accepted name compiles next to it,
// and with PoissonGlsl::ArrayForSnippets the kernels read it (SK_POISSON_TAPS / SK_POISSON_TAP_COUNT).
namespace {

std::string generated_taps(const char* name, shadowkit::PoissonGlsl mode, std::size_t n) {
    std::vector<glm::vec2> taps(n);
    REQUIRE(shadowkit::poisson_eliminate(shadowkit::PoissonDomain{}, n, 3, taps.data(), taps.size()).status ==
            shadowkit::Status::Ok);
    const shadowkit::PoissonGlslResult size = shadowkit::poisson_to_glsl(taps.data(), n, name, mode, nullptr, 0);
    REQUIRE(size.status == shadowkit::Status::BufferTooSmall);
    std::vector<char> text(size.needed);
    REQUIRE(shadowkit::poisson_to_glsl(taps.data(), n, name, mode, text.data(), text.size()).status == shadowkit::Status::Ok);
    return std::string(text.data());
}

// A fragment main() using both snippets' Poisson kernels and the user's own array.
const char* kBothKernels = R"(
uniform sampler2D u_depth;
uniform sampler2DShadow u_sm;
in vec3 v_uvz;
out vec4 o_color;
void main() {
    float a = sk_pcf_poisson(u_sm, v_uvz, vec2(0.0), 0.01, 16, 0.0);
    float b = sk_pcss(u_depth, u_sm, v_uvz, vec2(0.0), 0.5, 0.1, 50.0, 16, 16, 0.0, 0.05);
    o_color = vec4(a, b, SK_POISSON_DISK[31]);
}
)";

}  // namespace

namespace {
// Issue 25 item 2: cascades.glsl's filtered lookup exists only with pcf.glsl pasted first.
const char* kFilteredCascades = R"(
uniform sampler2DArrayShadow u_maps;
uniform mat4 u_vp[4];
uniform vec4 u_near;
uniform vec4 u_far;
in vec3 v_world;
in float v_depth;
out vec4 o_color;
void main() {
    float a = sk_cascade_shadow_filtered(u_maps, u_vp, u_near, u_far, 4, v_world, v_depth, 0.1, 1e-4, false,
                                         SK_CASCADE_KERNEL_TENT, 2, 16, 0.0);
    float b = sk_cascade_sample_filtered(u_maps, u_vp[1], 1, v_world, 1e-4, false, SK_CASCADE_KERNEL_POISSON_ROTATED,
                                         3, 16, 0.0);
    o_color = vec4(a, b, float(SK_CASCADE_KERNEL_HARD + SK_CASCADE_KERNEL_BOX + SK_CASCADE_KERNEL_POISSON), 1.0);
}
)";

}  // namespace

TEST_CASE("cascades.glsl after pcf.glsl has the filtered cascade lookup; alone it does not (issue 25.2)") {
    const std::string pcf = read_file(fs::path(SHADOWKIT_GLSL_DIR) / "pcf.glsl");
    const std::string cascades = read_file(fs::path(SHADOWKIT_GLSL_DIR) / "cascades.glsl");
    for (int v : {330, 450}) {
        const std::string src = "#version " + std::to_string(v) + " core\n" + pcf + cascades + kFilteredCascades;
        CHECK_MESSAGE(compile(src, EShLangFragment, v).empty(), compile(src, EShLangFragment, v));
    }
    // Control: without pcf.glsl the function is not declared (the check can fail).
    CHECK_FALSE(compile("#version 450 core\n" + cascades + kFilteredCascades, EShLangFragment, 450).empty());
}

// Issue 25 item 3: the two cube conventions have names that say what the cube holds; a call to an old,
// ambiguous name fails to compile with an identifier that names the new function.
TEST_CASE("cube lookups: the old names fail to compile and name the new ones (issue 25.3)") {
    const std::string shadow_map = read_file(fs::path(SHADOWKIT_GLSL_DIR) / "shadow_map.glsl");
    const std::string omni = read_file(fs::path(SHADOWKIT_GLSL_DIR) / "omni_shadow.glsl");
    const std::string decl = "uniform samplerCubeShadow u_cube;\nuniform samplerCube u_dist;\nin vec3 v_world;\nout vec4 o_color;\n";
    struct Case {
        const std::string* snippet;
        const char* call;
        const char* new_name;
    };
    const Case cases[] = {
        {&shadow_map, "sk_cube_shadow_visibility(u_cube, vec4(0.0, 0.0, 0.0, 1.0), v_world, 0.1, 10.0, 0.0)",
         "sk_cube_visibility_hardware_depth"},
        {&omni, "sk_omni_cube_shadow(u_cube, vec4(0.0, 0.0, 0.0, 1.0), v_world, 10.0, 0.0)", "sk_cube_visibility_distance"},
        {&omni, "sk_omni_cube_shadow_manual(u_dist, vec4(0.0, 0.0, 0.0, 1.0), v_world, 10.0, 0.0)",
         "sk_cube_visibility_distance_manual"},
        {&omni, "sk_omni_cube_pcf(u_cube, vec4(0.0, 0.0, 0.0, 1.0), v_world, 10.0, 0.0, 512.0, 1)",
         "sk_cube_visibility_distance_pcf"},
    };
    for (const Case& c : cases) {
        std::string old_call = c.call;
        const std::string old_src = "#version 450 core\n" + *c.snippet + decl + "void main() { o_color = vec4(" + old_call + "); }\n";
        const std::string err = compile(old_src, EShLangFragment, 450);
        CHECK_MESSAGE(err.find(std::string("renamed_to_") + c.new_name) != std::string::npos, err);
        // the same call under the new name compiles (the arguments are right: only the name was refused)
        const std::string new_call = c.new_name + old_call.substr(old_call.find('('));
        const std::string new_src = "#version 450 core\n" + *c.snippet + decl + "void main() { o_color = vec4(" + new_call + "); }\n";
        CHECK_MESSAGE(compile(new_src, EShLangFragment, 450).empty(), compile(new_src, EShLangFragment, 450));
    }
}

TEST_CASE("a generated Poisson array pasted before pcf.glsl and pcss.glsl compiles (issue 13.5)") {
    const std::string pcf = read_file(fs::path(SHADOWKIT_GLSL_DIR) / "pcf.glsl");
    const std::string pcss = read_file(fs::path(SHADOWKIT_GLSL_DIR) / "pcss.glsl");
    for (const char* version : {"330", "450"}) {
        const int v = std::atoi(version);
        // The array alone: the kernels keep the built-in disk; the user's array is theirs.
        const std::string arr = generated_taps("SK_POISSON_DISK", shadowkit::PoissonGlsl::Array, 32);
        std::string src = std::string("#version ") + version + " core\n" + arr + pcf + pcss +
                          "#if SK_POISSON_TAP_COUNT != 64\n#error built-in disk expected\n#endif\n" + kBothKernels;
        CHECK_MESSAGE(compile(src, EShLangFragment, v).empty(), compile(src, EShLangFragment, v));
        // With the switch: the kernels read the generated 32 taps.
        const std::string sw = generated_taps("SK_POISSON_DISK", shadowkit::PoissonGlsl::ArrayForSnippets, 32);
        src = std::string("#version ") + version + " core\n" + sw + pcf + pcss +
              "#if SK_POISSON_TAP_COUNT != 32\n#error generated taps expected\n#endif\n" + kBothKernels;
        CHECK_MESSAGE(compile(src, EShLangFragment, v).empty(), compile(src, EShLangFragment, v));
        // pcss.glsl before pcf.glsl works too (one guarded block).
        src = std::string("#version ") + version + " core\n" + sw + pcss + pcf + kBothKernels;
        CHECK(compile(src, EShLangFragment, v).empty());
    }
    // Control (the check can fail): an array under the snippets' own name is a redeclaration.
    const std::string clash = "#version 450 core\nconst vec2 sk_poisson_disk64[1] = vec2[1](vec2(0.0));\n" + pcf +
                              "out vec4 o_color;\nvoid main() { o_color = vec4(0.0); }\n";
    CHECK_FALSE(compile(clash, EShLangFragment, 450).empty());
}

TEST_CASE("every name poisson_to_glsl accepts compiles; glslang's reserved names are rejected (issue 19.6)") {
    // Seeded random identifiers, many near reserved words (keywords with a suffix, "__", gl_ / sk_).
    std::mt19937 rng(196);
    const std::string alphabet = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_0123456789";
    const char* stems[] = {"float", "if", "in", "out", "sample", "filter", "gl_", "sk_", "vec2", "input", "half",
                           "patch", "image2D", "common", "sizeof", "namespace", "__", "a__b", "texture", "SK_POISSON_DISK"};
    const glm::vec2 pts[2] = {{0.25f, 0.5f}, {-0.5f, 0.125f}};
    int accepted = 0, rejected = 0;
    for (int i = 0; i < 600; ++i) {
        std::string name;
        if (i % 3 == 0) name = stems[std::size_t(i / 3) % (sizeof stems / sizeof stems[0])];
        const int extra = (i % 3 == 0) ? int(rng() % 3) : 1 + int(rng() % 10);
        for (int k = 0; k < extra; ++k) name += alphabet[rng() % alphabet.size()];
        char text[512];
        const bool ok = shadowkit::poisson_to_glsl(pts, 2, name.c_str(), shadowkit::PoissonGlsl::Array, text, sizeof text)
                            .status == shadowkit::Status::Ok;
        const std::string src = std::string(ok ? text : "") + "out vec4 o_color;\nvoid main() { o_color = vec4(" +
                                name + "[1], 0.0, 1.0); }\n";
        if (!ok) {
            ++rejected;
            continue;
        }
        ++accepted;
        for (int v : {330, 450}) {
            const std::string err = compile("#version " + std::to_string(v) + " core\n" + src, EShLangFragment, v);
            INFO("name '" << name << "', GLSL " << v);
            CHECK_MESSAGE(err.empty(), err);
        }
    }
    // The issue's names, and every reserved word glslang refuses, are rejected.
    for (const char* bad : {"float", "if", "a__b", "gl_X", "filter", "input", "sample", "subroutine", "buffer"}) {
        char text[512];
        INFO(bad);
        CHECK(shadowkit::poisson_to_glsl(pts, 2, bad, shadowkit::PoissonGlsl::Array, text, sizeof text).status ==
              shadowkit::Status::InvalidArgument);
        const std::string raw = std::string("#version 450 core\nconst vec2 ") + bad + "[1] = vec2[1](vec2(0.0));\n" +
                                "out vec4 o_color;\nvoid main() { o_color = vec4(0.0); }\n";
        if (std::string(bad) != "a__b") CHECK_FALSE(compile(raw, EShLangFragment, 450).empty());  // glslang: an error
    }
    MESSAGE(accepted << " random names accepted (each compiles with glslang at 330 and 450), " << rejected << " rejected");
    CHECK(accepted > 300);
    CHECK(rejected > 50);
}

// ---------------------------------------------------------------------------------------------
// Vulkan: the snippets take samplers, matrices and parameters as function arguments, so they are
// Vulkan GLSL as they stand. Proof: every snippet with version 450 compiles to SPIR-V (Vulkan 1.0
// rules) together with a Vulkan form of its driver, in which every loose uniform is declared in a
// descriptor set: opaque types get their own binding, the rest go into one std140 uniform block;
// stage inputs and outputs get explicit locations; gl_VertexID becomes gl_VertexIndex. The SPIR-V
// is written to the build tree and checked with spirv-val where it is installed.
namespace {

bool is_opaque(const std::string& type) {
    return type.find("sampler") != std::string::npos || type.find("image") != std::string::npos;
}

// The Vulkan form of a GL driver (see above).
std::string vulkan_driver(const std::string& gl) {
    std::istringstream in(gl);
    std::ostringstream out, block;
    std::string line;
    int binding = 1, in_loc = 0, out_loc = 0;  // binding 0 is left to the snippets' own buffers
    bool any_block_member = false;
    auto first_word = [](const std::string& s, std::size_t from) {
        std::size_t a = s.find_first_not_of(" \t", from), b = s.find_first_of(" \t;[", a);
        return a == std::string::npos ? std::string() : s.substr(a, b - a);
    };
    while (std::getline(in, line)) {
        std::size_t p = line.find_first_not_of(" \t");
        const std::string t = p == std::string::npos ? std::string() : line.substr(p);
        if (t.rfind("uniform ", 0) == 0) {
            const std::string type = first_word(t, 8);
            if (is_opaque(type)) {
                out << "layout(set = 0, binding = " << binding++ << ") " << t << '\n';
            } else {
                block << "    " << t.substr(8) << '\n';
                any_block_member = true;
            }
            continue;
        }
        std::string q = t;
        std::string interp;
        for (const char* w : {"flat ", "noperspective ", "smooth "})
            if (q.rfind(w, 0) == 0) {
                interp = w;
                q = q.substr(interp.size());
            }
        if (t.find("layout") != 0 && (q.rfind("in ", 0) == 0 || q.rfind("out ", 0) == 0)) {
            const bool is_in = q[0] == 'i';
            out << "layout(location = " << (is_in ? in_loc++ : out_loc++) << ") " << interp << q << '\n';
            continue;
        }
        for (std::size_t k; (k = line.find("gl_VertexID")) != std::string::npos;)
            line.replace(k, 11, "gl_VertexIndex");
        out << line << '\n';
    }
    if (!any_block_member) return out.str();
    return "layout(set = 0, binding = " + std::to_string(binding) + ", std140) uniform SkDriverParams {\n" +
           block.str() + "};\n" + out.str();
}

// Compiles one stage for Vulkan 1.0 and returns "" (and the SPIR-V) or the log.
std::string compile_vulkan(const std::string& source, EShLanguage lang, std::vector<unsigned>& spirv) {
    glslang::TShader shader(lang);
    const char* text = source.c_str();
    shader.setStrings(&text, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, lang, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_0);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_0);
    const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
    if (!shader.parse(GetDefaultResources(), 450, ECoreProfile, false, false, messages))
        return std::string("compile: ") + shader.getInfoLog();
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) return std::string("link: ") + program.getInfoLog();
    spirv.clear();
    glslang::GlslangToSpv(*program.getIntermediate(lang), spirv);
    return spirv.empty() ? std::string("no SPIR-V") : std::string();
}

}  // namespace

TEST_CASE("every glsl/ snippet compiles to SPIR-V for Vulkan with descriptor-set bindings") {
    const fs::path out_dir = fs::path(SHADOWKIT_GLSL_SPIRV_DIR);
    fs::create_directories(out_dir);
    const bool have_val = std::system("spirv-val --version > /dev/null 2>&1") == 0;
    int compiled = 0, validated = 0, snippets = 0;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(SHADOWKIT_GLSL_DIR))
        if (e.path().extension() == ".glsl") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        const std::string src = read_file(f), stem = f.stem().string();
        std::vector<std::string> versions, stages;
        REQUIRE_MESSAGE(parse_header(src, versions, stages), stem);
        if (std::find(versions.begin(), versions.end(), "450") == versions.end()) {
            FAIL_CHECK(stem << ": declares no version 450, so it is not checked as Vulkan GLSL");
            continue;
        }
        ++snippets;
        for (const auto& st : stages) {
            EShLanguage lang{};
            REQUIRE(stage_of(st, lang));
            const fs::path driver = fs::path(SHADOWKIT_GLSL_DRIVER_DIR) / (stem + "." + st + ".glsl");
            if (!fs::exists(driver)) continue;  // reported by the GL test above
            const std::string full = "#version 450 core\n#line 1\n" + src + "\n#line 1\n" + vulkan_driver(read_file(driver));
            std::vector<unsigned> spirv;
            const std::string err = compile_vulkan(full, lang, spirv);
            if (!err.empty()) {
                FAIL_CHECK(stem << " (" << st << ", Vulkan): " << err);
                continue;
            }
            ++compiled;
            const fs::path spv = out_dir / (stem + "." + st + ".spv");
            std::ofstream(out_dir / (stem + "." + st + ".vk.glsl")) << full;
            std::ofstream(spv, std::ios::binary)
                .write(reinterpret_cast<const char*>(spirv.data()), static_cast<std::streamsize>(spirv.size() * 4));
            if (have_val) {
                const std::string cmd = "spirv-val --target-env vulkan1.0 '" + spv.string() + "'";
                CHECK_MESSAGE(std::system(cmd.c_str()) == 0, "spirv-val rejects " << spv.string());
                ++validated;
            }
        }
    }
    MESSAGE(snippets << " snippets, " << compiled << " (snippet, stage) SPIR-V modules, " << validated
                     << " validated by spirv-val");
    CHECK(compiled >= snippets);
}

TEST_CASE("the Vulkan form of a driver puts loose uniforms into a set (the transform can fail)") {
    const std::string v = vulkan_driver("uniform sampler2DShadow u_sm;\nuniform mat4 u_m;\nin vec3 v_p;\nout vec4 o;\n"
                                        "void main() { o = vec4(gl_VertexID); }\n");
    CHECK(v.find("layout(set = 0, binding = 1) uniform sampler2DShadow u_sm;") != std::string::npos);
    CHECK(v.find("uniform SkDriverParams {\n    mat4 u_m;\n};") != std::string::npos);
    CHECK(v.find("layout(location = 0) in vec3 v_p;") != std::string::npos);
    CHECK(v.find("layout(location = 0) out vec4 o;") != std::string::npos);
    CHECK(v.find("gl_VertexIndex") != std::string::npos);
    // and a loose uniform is an error under Vulkan rules, so the transform is what makes it compile
    std::vector<unsigned> spirv;
    CHECK(compile_vulkan("#version 450 core\nuniform float u_x;\nlayout(location = 0) out vec4 o;\nvoid main() { o = vec4(u_x); }\n",
                         EShLangFragment, spirv) != "");
}

namespace {
// Issue 25 (SDSM): the reduction passes the cascaded sample runs, each a full-screen fragment shader
// of cascades.glsl's reduction functions (the bounds pass writes four targets).
const char* kSdsmPasses[] = {
    R"(
uniform sampler2D u_src;
out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_depth(u_src, ivec2(gl_FragCoord.xy), 8, 1.0); }
)",
    R"(
uniform sampler2D u_src;
out vec2 o_minmax;
void main() { o_minmax = sk_sdsm_reduce_minmax(u_src, ivec2(gl_FragCoord.xy), 8); }
)",
    R"(
uniform sampler2D u_src;
uniform mat4 u_c2w, u_w2v, u_w2l;
uniform vec4 u_split_far;
layout(location = 0) out vec4 o_b0;
layout(location = 1) out vec4 o_b1;
layout(location = 2) out vec4 o_b2;
layout(location = 3) out vec4 o_b3;
void main() {
    vec4 b[4];
    sk_sdsm_reduce_bounds(u_src, ivec2(gl_FragCoord.xy), 8, 0.0, u_c2w, u_w2v, u_w2l, u_split_far, 4, true, b);
    o_b0 = b[0]; o_b1 = b[1]; o_b2 = b[2]; o_b3 = b[3];
}
)",
    R"(
uniform sampler2D u_l0;
out vec4 o_b;
void main() { o_b = sk_sdsm_reduce_bounds_level(u_l0, ivec2(gl_FragCoord.xy), 8) + vec4(SK_SDSM_EMPTY_MIN + SK_SDSM_EMPTY_MAX); }
)"};
}  // namespace

TEST_CASE("cascades.glsl's SDSM reduction passes compile (GLSL 3.30 and 4.50, fragment stage)") {
    const std::string cascades = read_file(fs::path(SHADOWKIT_GLSL_DIR) / "cascades.glsl");
    for (int v : {330, 450})
        for (const char* pass : kSdsmPasses) {
            const std::string src = "#version " + std::to_string(v) + " core\n" + cascades + pass;
            CHECK_MESSAGE(compile(src, EShLangFragment, v).empty(), compile(src, EShLangFragment, v));
        }
    // Control: a call with the bounds out of order does not compile (the check can fail).
    CHECK_FALSE(compile("#version 450 core\n" + cascades +
                            "out vec2 o; uniform sampler2D s; void main() { o = sk_sdsm_reduce_minmax(s, 8, ivec2(0)); }",
                        EShLangFragment, 450)
                    .empty());
}

// Every hlsl/*.hlsl snippet compiles with glslang's HLSL front end (in process) to SPIR-V for Vulkan
// 1.1 as a complete pixel shader: the snippet + the driver tests/hlsl/<snippet>.hlsl, whose main()
// calls every function of the snippet (a driver's "// needs: pcf" line pastes hlsl/pcf.hlsl first); the module is checked by spirv-val where it is installed.
// Every hlsl/ snippet has a glsl/ twin of the same name; a snippet without a driver fails, and a
// broken fixture must fail. (The snippets RUN on Vulkan in tests/vulkan/, labels vulkan and hlsl;
// this check needs only glslang.) DXC is not packaged in Debian 12 and is not run.
// Parity: every sk_ function defined in glsl/X.glsl is defined in hlsl/X.hlsl and vice versa (but for
// the short lists below, each with its reason), and a GLSL parameter named bias_* (a bias names its
// unit) has the same name in the HLSL twin.
#include <doctest/doctest.h>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <set>
#include <filesystem>
#include <fstream>
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

// Compiles a pixel shader (entry `main`) to SPIR-V; "" or the log.
std::string compile_hlsl(const std::string& source, std::vector<unsigned>& spirv) {
    glslang::TShader shader(EShLangFragment);
    const char* text = source.c_str();
    shader.setStrings(&text, 1);
    shader.setEntryPoint("main");
    shader.setSourceEntryPoint("main");
    shader.setEnvInput(glslang::EShSourceHlsl, EShLangFragment, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
    const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules | EShMsgReadHlsl);
    if (!shader.parse(GetDefaultResources(), 100, false, messages)) return std::string("compile: ") + shader.getInfoLog();
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) return std::string("link: ") + program.getInfoLog();
    glslang::SpvOptions opt;
    opt.disableOptimizer = false;  // SPIRV-Tools legalization, as glslangValidator -D runs it
    spirv.clear();
    glslang::GlslangToSpv(*program.getIntermediate(EShLangFragment), spirv, &opt);
    return spirv.empty() ? std::string("no SPIR-V") : std::string();
}

// Checks one snippet with its driver; returns "" or what failed (and counts spirv-val runs).
std::string check_snippet(const fs::path& snippet, const fs::path& driver_dir, const fs::path& out_dir, int& validated) {
    const std::string stem = snippet.stem().string();
    const fs::path driver = driver_dir / (stem + ".hlsl");
    if (!fs::exists(driver)) return stem + ": missing driver " + driver.string();
    // a driver line "// needs: a b" pastes hlsl/a.hlsl, hlsl/b.hlsl before the snippet
    const std::string drv = read_file(driver);
    std::string prefix;
    const auto needs = drv.find("// needs:");
    if (needs != std::string::npos) {
        std::istringstream names(drv.substr(needs + 9, drv.find('\n', needs) - needs - 9));
        for (std::string n; names >> n;) prefix += read_file(snippet.parent_path() / (n + ".hlsl")) + "\n";
    }
    std::vector<unsigned> spirv;
    const std::string err = compile_hlsl(prefix + read_file(snippet) + "\n" + drv, spirv);
    if (!err.empty()) return stem + ": " + err;
    fs::create_directories(out_dir);
    const fs::path spv = out_dir / (stem + ".hlsl.spv");
    std::ofstream(spv, std::ios::binary)
        .write(reinterpret_cast<const char*>(spirv.data()), static_cast<std::streamsize>(spirv.size() * 4));
    if (std::system("spirv-val --version > /dev/null 2>&1") != 0) return {};
    ++validated;
    const std::string cmd = "spirv-val --target-env vulkan1.1 '" + spv.string() + "'";
    return std::system(cmd.c_str()) == 0 ? std::string() : stem + ": spirv-val rejects " + spv.string();
}

// sk_ function definitions of a GLSL or HLSL source: name -> parameter names (overloads merged).
// A definition is a line "type... sk_name(params)" (not a comment) whose ')' is followed by '{'.
std::map<std::string, std::set<std::string>> sk_definitions(const std::string& src) {
    std::map<std::string, std::set<std::string>> out;
    std::size_t pos = 0;
    while ((pos = src.find("sk_", pos)) != std::string::npos) {
        const std::size_t start = pos;
        pos += 3;
        if (start > 0 && (std::isalnum(static_cast<unsigned char>(src[start - 1])) != 0 || src[start - 1] == '_')) continue;
        std::size_t e = start;
        while (e < src.size() && (std::isalnum(static_cast<unsigned char>(src[e])) != 0 || src[e] == '_')) ++e;
        const std::string name = src.substr(start, e - start);
        // the line before the name: only type words and blanks (no '=', '(', "//", "#", "return")
        const std::size_t bol = src.rfind('\n', start) == std::string::npos ? 0 : src.rfind('\n', start) + 1;
        const std::string head = src.substr(bol, start - bol);
        if (head.find_first_not_of(" \t") == std::string::npos) continue;  // a type word is needed
        if (head.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_ \t") != std::string::npos)
            continue;
        if (head.find("return") != std::string::npos) continue;
        std::size_t p = e;
        while (p < src.size() && std::isspace(static_cast<unsigned char>(src[p])) != 0) ++p;
        if (p >= src.size() || src[p] != '(') continue;
        const std::size_t close = src.find(')', p);
        if (close == std::string::npos) break;
        std::size_t b = close + 1;
        while (b < src.size() && std::isspace(static_cast<unsigned char>(src[b])) != 0) ++b;
        if (b >= src.size() || src[b] != '{') continue;
        auto& params = out[name];
        std::istringstream list(src.substr(p + 1, close - p - 1));
        for (std::string param; std::getline(list, param, ',');) {
            param = param.substr(0, param.find('['));
            std::size_t last = param.find_last_not_of(" \t\n");
            if (last == std::string::npos) continue;
            std::size_t first = last;
            while (first > 0 && (std::isalnum(static_cast<unsigned char>(param[first - 1])) != 0 || param[first - 1] == '_')) --first;
            params.insert(param.substr(first, last + 1 - first));
        }
    }
    return out;
}

// What differs between a GLSL snippet and its HLSL twin ("" when they match): sk_ functions on one side
// only (less the allowed lists), and bias_* parameters of the GLSL not named so in the HLSL.
std::string parity(const std::string& stem, const std::string& glsl, const std::string& hlsl,
                   const std::set<std::string>& glsl_only, const std::set<std::string>& hlsl_only) {
    const auto g = sk_definitions(glsl);
    const auto h = sk_definitions(hlsl);
    std::string out;
    for (const auto& [name, params] : g) {
        const auto it = h.find(name);
        if (it == h.end()) {
            if (glsl_only.count(name) == 0) out += " " + name + " (GLSL only)";
            continue;
        }
        for (const auto& param : params)
            if (param.rfind("bias", 0) == 0 && it->second.count(param) == 0)
                out += " " + name + "'s parameter " + param + " (named differently in HLSL)";
    }
    for (const auto& kv : h)
        if (g.count(kv.first) == 0 && hlsl_only.count(kv.first) == 0) out += " " + kv.first + " (HLSL only)";
    return out.empty() ? out : stem + ":" + out;
}

// Functions allowed on one side only, each with its reason.
const std::set<std::string> kGlslOnly = {
    // none today: a stage-specific GLSL helper with no HLSL meaning would be listed here
};
const std::set<std::string> kHlslOnly = {
    "sk_pcss_tap_offset",  // the rotated Poisson tap: GLSL writes mat2(c, s, -s, c) * tap inline
    // virtual_shadow_map: GLSL reads its SSBO's members by name; HLSL's ByteAddressBuffer needs accessors
    "sk_vsm_world_to_uv", "sk_vsm_origin", "sk_vsm_layout", "sk_vsm_flags", "sk_vsm_scale", "sk_vsm_table",
};

}  // namespace

TEST_CASE("every hlsl/ snippet compiles with glslang's HLSL front end to valid SPIR-V, and has a glsl/ twin") {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(SHADOWKIT_HLSL_DIR))
        if (e.path().extension() == ".hlsl") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    int validated = 0;
    for (const auto& f : files) {
        const std::string err = check_snippet(f, SHADOWKIT_HLSL_DRIVER_DIR, SHADOWKIT_HLSL_SPIRV_DIR, validated);
        CHECK_MESSAGE(err.empty(), err);
        const fs::path twin = fs::path(SHADOWKIT_GLSL_DIR) / (f.stem().string() + ".glsl");
        CHECK_MESSAGE(fs::exists(twin), f.filename().string() << " has no GLSL twin " << twin.string());
        const std::string src = read_file(f);
        CHECK_MESSAGE(src.find("MIT License. Copyright (c) shadowkit contributors.") != std::string::npos, f.string());
    }
    MESSAGE(files.size() << " HLSL snippets compiled, " << validated << " validated by spirv-val");
    CHECK(files.size() >= 2);
}

TEST_CASE("a broken HLSL snippet fails the compile check, a missing driver fails (the check can fail)") {
    int validated = 0;
    const fs::path fixtures(SHADOWKIT_GLSL_FIXTURE_DIR);
    const std::string broken = check_snippet(fixtures / "broken.hlsl", fixtures / "hlsl_drivers", SHADOWKIT_HLSL_SPIRV_DIR, validated);
    CHECK(broken.find("compile") != std::string::npos);
    const std::string missing = check_snippet(fixtures / "broken.hlsl", fixtures / "no_drivers_here", SHADOWKIT_HLSL_SPIRV_DIR, validated);
    CHECK(missing.find("missing driver") != std::string::npos);
}

TEST_CASE("every sk_ function of glsl/X.glsl is defined in hlsl/X.hlsl and vice versa, bias_* names match") {
    std::set<std::string> hlsl_defined;
    int pairs = 0;
    for (const auto& e : fs::directory_iterator(SHADOWKIT_GLSL_DIR)) {
        if (e.path().extension() != ".glsl") continue;
        const std::string stem = e.path().stem().string();
        const fs::path twin = fs::path(SHADOWKIT_HLSL_DIR) / (stem + ".hlsl");
        CHECK_MESSAGE(fs::exists(twin), stem << ".glsl has no HLSL twin " << twin.string());
        if (!fs::exists(twin)) continue;
        ++pairs;
        const std::string glsl = read_file(e.path()), hlsl = read_file(twin);
        CHECK_MESSAGE(!sk_definitions(glsl).empty(), stem << ": no sk_ function found in the GLSL (the parser is broken)");
        const std::string diff = parity(stem, glsl, hlsl, kGlslOnly, kHlslOnly);
        CHECK_MESSAGE(diff.empty(), diff);
        for (const auto& kv : sk_definitions(hlsl)) hlsl_defined.insert(kv.first);
    }
    // the allowed lists hold no stale entry: each HLSL-only name is still defined in some HLSL twin
    for (const auto& name : kHlslOnly) CHECK_MESSAGE(hlsl_defined.count(name) == 1, name << " is listed but not defined");
    MESSAGE(pairs << " GLSL / HLSL pairs compared");
    CHECK(pairs >= 16);
}

TEST_CASE("the parity check finds a missing function, an extra one and a renamed bias (the check can fail)") {
    const std::string glsl = "// sk_commented(float x) {\nfloat sk_a(float bias_window, sampler2DShadow m)\n{\n"
                             "    return sk_b(bias_window);\n}\nvec2 sk_b(float x) { return vec2(x); }\n";
    CHECK(sk_definitions(glsl).size() == 2);
    CHECK(sk_definitions(glsl).at("sk_a").count("bias_window") == 1);
    const std::string same = "float sk_a(Texture2D<float> m, SamplerComparisonState cmp, float bias_window) {\n"
                             "    return sk_b(bias_window).x;\n}\nfloat2 sk_b(float x) { return float2(x, x); }\n";
    CHECK(parity("t", glsl, same, {}, {}).empty());
    const std::string missing = "float sk_a(float bias_window) { return 1.0; }\nfloat sk_c(float x) { return x; }\n";
    const std::string d = parity("t", glsl, missing, {}, {});
    CHECK(d.find("sk_b (GLSL only)") != std::string::npos);
    CHECK(d.find("sk_c (HLSL only)") != std::string::npos);
    CHECK(parity("t", glsl, missing, {"sk_b"}, {"sk_c"}).empty());
    const std::string renamed = "float sk_a(float bias) { return 1.0; }\nfloat2 sk_b(float x) { return float2(x, x); }\n";
    CHECK(parity("t", glsl, renamed, {}, {}).find("sk_a's parameter bias_window") != std::string::npos);
}

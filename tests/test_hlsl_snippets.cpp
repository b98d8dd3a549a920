// Every hlsl/*.hlsl snippet compiles with glslang's HLSL front end (in process) to SPIR-V for Vulkan
// 1.1 as a complete pixel shader: the snippet + the driver tests/hlsl/<snippet>.hlsl, whose main()
// calls every function of the snippet (a driver's "// needs: pcf" line pastes hlsl/pcf.hlsl first); the module is checked by spirv-val where it is installed.
// Every hlsl/ snippet has a glsl/ twin of the same name; a snippet without a driver fails, and a
// broken fixture must fail. (The snippets RUN on Vulkan in tests/vulkan/, labels vulkan and hlsl;
// this check needs only glslang.) DXC is not packaged in Debian 12 and is not run.
#include <doctest/doctest.h>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <algorithm>
#include <cstdlib>
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

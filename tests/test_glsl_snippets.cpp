// Every glsl/*.glsl snippet compiles with glslang (library API, in process) for every GLSL version
// and stage its header comment declares, as a complete shader: "#version V core" + snippet +
// the driver tests/glsl/<snippet>.<stage>.glsl whose main() calls the snippet's functions.
// A snippet without a driver for a declared stage fails; a broken fixture must fail.
#include <doctest/doctest.h>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
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

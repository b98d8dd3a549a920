// docs_extract - pulls the code blocks out of README.md and docs/*.md for the CTest label `docs`
// (the rules are in tests/CONVENTIONS.md, "Documentation blocks"). Built and run by CMake at
// configure time; writes the blocks and a manifest that tests/docs/CMakeLists.txt includes:
//   OUT/complete/<doc>_<line>.cpp     a C++ block with `int main(`: compiled alone and run
//   OUT/parts/<NAME>/<PART>.inc       a block after `<!-- example: NAME/PART -->`, #included by
//                                     tests/docs/NAME.cpp
//   OUT/glsl/<doc>_<line>.glsl        a GLSL block after `<!-- glsl: STAGE VERSION snippets: a b -->`
//   OUT/hlsl/<doc>_<line>.hlsl        an HLSL block after `<!-- hlsl: STAGE ENTRY snippets: a b -->`
//   OUT/manifest.cmake                the lists above, and every rule broken (DOCS_ERRORS)
// Usage: docs_extract OUT PROGRAMS_DIR file.md...
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string trim(const std::string& s) {
    const auto a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return "";
    const auto b = s.find_last_not_of(" \t\r");
    return s.substr(a, b - a + 1);
}

// CMake bracket argument, safe for any text.
std::string cm(const std::string& s) { return "[==[" + s + "]==]"; }

bool write_if_changed(const fs::path& p, const std::string& text) {
    std::ifstream in(p, std::ios::binary);
    if (in) {
        std::stringstream old;
        old << in.rdbuf();
        if (old.str() == text) return true;
    }
    fs::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary);
    out << text;
    return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: docs_extract OUT PROGRAMS_DIR file.md...\n");
        return 2;
    }
    const fs::path out = argv[1];
    const fs::path programs = argv[2];
    std::vector<std::string> errors;
    std::ostringstream complete, glsl, hlsl, parts_list;
    std::map<std::string, std::set<std::string>> parts;  // example name -> parts found in the docs
    std::set<std::string> written;
    const std::regex example_re(R"(^<!--\s*example:\s*([A-Za-z0-9_]+)/([A-Za-z0-9_]+)\s*-->$)");
    const std::regex glsl_re(R"(^<!--\s*glsl:\s*(vertex|fragment|geometry|compute)\s+([0-9]+)\s+snippets:\s*([A-Za-z0-9_ ]*)-->$)");
    const std::regex hlsl_re(R"(^<!--\s*hlsl:\s*(vertex|geometry|pixel|compute)\s+([A-Za-z_][A-Za-z0-9_]*)\s+snippets:\s*([A-Za-z0-9_ ]*)-->$)");
    int cpp_blocks = 0, glsl_blocks = 0, hlsl_blocks = 0;

    for (int a = 3; a < argc; ++a) {
        const fs::path md = argv[a];
        std::ifstream in(md);
        if (!in) {
            errors.push_back("cannot read " + md.string());
            continue;
        }
        std::vector<std::string> lines;
        for (std::string l; std::getline(in, l);) lines.push_back(l);
        const std::string doc = md.parent_path().filename().string() == "docs" ? "docs_" + md.stem().string()
                                                                               : md.stem().string();
        const std::string shown = (md.parent_path().filename().string() == "docs" ? "docs/" : "") +
                                  md.filename().string();
        for (std::size_t i = 0; i < lines.size(); ++i) {
            const std::string t = trim(lines[i]);
            if (t.rfind("```", 0) != 0) continue;
            const std::string lang = trim(t.substr(3));
            std::size_t end = i + 1;
            while (end < lines.size() && trim(lines[end]).rfind("```", 0) != 0) ++end;
            std::string body;
            for (std::size_t k = i + 1; k < end; ++k) body += lines[k] + "\n";
            const std::string marker = i > 0 ? trim(lines[i - 1]) : "";
            const int line_no = static_cast<int>(i) + 2;  // first line of the block, 1-based
            const std::string where = shown + ":" + std::to_string(line_no);
            const std::string id = doc + "_" + std::to_string(line_no);
            std::smatch m;
            if (lang == "cpp" || lang == "c++" || lang == "c") {
                ++cpp_blocks;
                const std::string line_directive = "#line " + std::to_string(line_no) + " \"" + shown + "\"\n";
                if (std::regex_match(marker, m, example_re)) {
                    const std::string name = m[1], part = m[2];
                    if (!parts[name].insert(part).second)
                        errors.push_back(where + ": part " + name + "/" + part + " appears twice");
                    write_if_changed(out / "parts" / name / (part + ".inc"), line_directive + body);
                    written.insert((fs::path("parts") / name / (part + ".inc")).string());
                    parts_list << "  " << cm(name + "/" + part) << "\n";
                } else if (body.find("int main(") != std::string::npos) {
                    write_if_changed(out / "complete" / (id + ".cpp"), line_directive + body);
                    written.insert((fs::path("complete") / (id + ".cpp")).string());
                    complete << "  " << cm(id) << "\n";
                } else {
                    errors.push_back(where + ": a C++ block with no `int main(` and no `<!-- example: NAME/PART -->` line before it");
                }
            } else if (lang == "glsl") {
                ++glsl_blocks;
                if (!std::regex_match(marker, m, glsl_re)) {
                    errors.push_back(where + ": a GLSL block needs `<!-- glsl: STAGE VERSION snippets: a b -->` on the line before it");
                } else {
                    write_if_changed(out / "glsl" / (id + ".glsl"), body);
                    written.insert((fs::path("glsl") / (id + ".glsl")).string());
                    glsl << "  " << cm(id + "|" + std::string(m[1]) + "|" + std::string(m[2]) + "|" + trim(m[3]) + "|" + where) << "\n";
                }
            } else if (lang == "hlsl") {
                ++hlsl_blocks;
                if (!std::regex_match(marker, m, hlsl_re)) {
                    errors.push_back(where + ": an HLSL block needs `<!-- hlsl: STAGE ENTRY snippets: a b -->` on the line before it");
                } else {
                    write_if_changed(out / "hlsl" / (id + ".hlsl"), body);
                    written.insert((fs::path("hlsl") / (id + ".hlsl")).string());
                    hlsl << "  " << cm(id + "|" + std::string(m[1]) + "|" + std::string(m[2]) + "|" + trim(m[3]) + "|" + where) << "\n";
                }
            }
            i = end;
        }
    }

    // Every part is included by its program, and every included part exists.
    std::set<std::string> program_names;
    if (fs::is_directory(programs)) {
        const std::regex inc_re(R"re(^\s*#\s*include\s*"([A-Za-z0-9_]+)\.inc")re");
        for (const auto& e : fs::directory_iterator(programs)) {
            if (e.path().extension() != ".cpp" || e.path().stem() == "docs_extract") continue;
            const std::string name = e.path().stem().string();
            program_names.insert(name);
            std::ifstream in(e.path());
            std::set<std::string> included;
            for (std::string l; std::getline(in, l);) {
                std::smatch m;
                if (std::regex_search(l, m, inc_re)) included.insert(m[1]);
            }
            for (const auto& p : included)
                if (!parts[name].count(p))
                    errors.push_back("tests/docs/" + name + ".cpp includes " + p + ".inc, but no docs block is named " + name + "/" + p);
            for (const auto& p : parts[name])
                if (!included.count(p))
                    errors.push_back("docs block " + name + "/" + p + " is not included by tests/docs/" + name + ".cpp");
        }
    }
    for (const auto& [name, ps] : parts)
        if (!ps.empty() && !program_names.count(name))
            errors.push_back("docs blocks name the example " + name + ", but tests/docs/" + name + ".cpp does not exist");

    // Stale files from renamed blocks would be harmless, but keep the tree exact.
    for (const char* sub : {"complete", "parts", "glsl", "hlsl"}) {
        if (!fs::exists(out / sub)) continue;
        for (const auto& e : fs::recursive_directory_iterator(out / sub))
            if (e.is_regular_file() && !written.count(fs::relative(e.path(), out).string())) fs::remove(e.path());
    }

    std::ostringstream manifest;
    manifest << "# written by docs_extract: do not edit\n";
    manifest << "set(DOCS_CPP_BLOCKS " << cpp_blocks << ")\nset(DOCS_GLSL_BLOCKS " << glsl_blocks << ")\n";
    manifest << "set(DOCS_COMPLETE\n" << complete.str() << ")\n";
    manifest << "set(DOCS_PARTS\n" << parts_list.str() << ")\n";
    manifest << "set(DOCS_GLSL\n" << glsl.str() << ")\n";
    manifest << "set(DOCS_HLSL_BLOCKS " << hlsl_blocks << ")\nset(DOCS_HLSL\n" << hlsl.str() << ")\n";
    manifest << "set(DOCS_PROGRAMS\n";
    for (const auto& p : program_names) manifest << "  " << cm(p) << "\n";
    manifest << ")\nset(DOCS_ERRORS\n";
    for (const auto& e : errors) manifest << "  " << cm(e) << "\n";
    manifest << ")\n";
    write_if_changed(out / "manifest.cmake", manifest.str());
    return 0;
}

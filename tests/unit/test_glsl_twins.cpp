// Constants shared by a GLSL snippet (glsl/NAME.glsl) and its header (include/shadowkit/NAME.hpp),
// checked on the CPU (no GL context: runs in the headers-only CI step). The snippets are parsed as
// text:
//  1. Twin functions: the GLSL function and its C++ counterpart carry the same numeric literals in
//     the same order (named constants - constexpr in the header, #define / const in the snippet -
//     replaced by their values first). Catches a drift of the MSM quantization matrices, the
//     exponent limits, the rounding-error terms and the NaN / Inf fallbacks (return 1.0 vs 0.0).
//  2. Every literal with 6 or more significant digits in a snippet (a constant someone computed)
//     appears in its header, or equals a closed form to its printed precision (pi, 2 pi, FLT_MAX,
//     ln FLT_MAX, ...), or is one of the few GLSL-only constants listed below with their reason.
#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

std::string read_source(const std::string& rel) {
    std::ifstream f(std::string(SHADOWKIT_SOURCE_DIR) + "/" + rel);
    REQUIRE_MESSAGE(f.good(), "cannot read " << rel);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// (Hand-written scanners, not std::regex: GCC 12's <regex> trips -Wmaybe-uninitialized under the
// sanitizer preset's -O1.)
bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

std::string strip_comments(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size();) {
        if (s.compare(i, 2, "//") == 0) {
            while (i < s.size() && s[i] != '\n') ++i;
        } else if (s.compare(i, 2, "/*") == 0) {
            const std::size_t e = s.find("*/", i + 2);
            i = e == std::string::npos ? s.size() : e + 2;
            out += ' ';
        } else {
            out += s[i++];
        }
    }
    return out;
}

// The numeric literal starting at i (digits, '.', exponent; an f/u suffix skipped), its text without
// the suffix in `lit`; the position after it. 0 length: no literal (part of an identifier, or none).
std::size_t scan_literal(const std::string& s, std::size_t i, std::string& lit) {
    lit.clear();
    if (i > 0 && (ident_char(s[i - 1]) || s[i - 1] == '.')) return i;
    std::size_t j = i;
    bool digits = false;
    while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j, digits = true;
    if (j < s.size() && s[j] == '.') {
        ++j;
        while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j, digits = true;
    }
    if (!digits) return i;
    if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
        std::size_t k = j + 1;
        if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
        if (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) {
            while (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) ++k;
            j = k;
        }
    }
    const std::size_t end_number = j;
    if (j < s.size() && (s[j] == 'f' || s[j] == 'F' || s[j] == 'u' || s[j] == 'U')) ++j;
    if (j < s.size() && (ident_char(s[j]) || s[j] == '.')) return i;
    lit = s.substr(i, end_number - i);
    return j;
}

std::vector<std::pair<std::size_t, std::string>> literal_positions(const std::string& code) {
    std::vector<std::pair<std::size_t, std::string>> out;
    std::string lit;
    for (std::size_t i = 0; i < code.size();) {
        const std::size_t j = scan_literal(code, i, lit);
        if (!lit.empty()) {
            out.emplace_back(i, lit);
            i = j;
        } else {
            ++i;
            while (i < code.size() && ident_char(code[i]) && ident_char(code[i - 1])) ++i;  // skip identifiers whole
        }
    }
    return out;
}

std::vector<std::string> literals(const std::string& code) {
    std::vector<std::string> out;
    for (const auto& pl : literal_positions(code)) out.push_back(pl.second);
    return out;
}

// The arithmetic operator before each literal ('+', '-', '*', '/', or ' ' for anything else): a
// sign or an operation that drifts shows even when the value does not.
std::string operators(const std::string& code) {
    std::string out;
    for (const auto& pl : literal_positions(code)) {
        std::size_t i = pl.first;
        while (i > 0 && std::isspace(static_cast<unsigned char>(code[i - 1]))) --i;
        const char c = i > 0 ? code[i - 1] : ' ';
        out += (c == '+' || c == '-' || c == '*' || c == '/') ? c : ' ';
    }
    return out;
}

std::vector<double> values(const std::vector<std::string>& lits) {
    std::vector<double> v;
    for (const std::string& l : lits) v.push_back(std::strtod(l.c_str(), nullptr));
    return v;
}

std::string join(const std::vector<std::string>& v) {
    std::string out;
    for (const std::string& x : v) out += (out.empty() ? "" : ", ") + x;
    return out;
}

std::string trim(const std::string& s) {
    const std::size_t a = s.find_first_not_of(" \t\r");
    if (a == std::string::npos) return std::string();
    return s.substr(a, s.find_last_not_of(" \t\r") + 1 - a);
}

// Named constants, one per line: `constexpr T NAME = LITERAL;` (header), `#define NAME LITERAL` and
// `const float NAME = LITERAL;` (snippet).
std::map<std::string, std::string> named_constants(const std::string& code) {
    std::map<std::string, std::string> out;
    std::istringstream in(code);
    std::string line, lit;
    while (std::getline(in, line)) {
        line = trim(line);
        std::string name, value;
        if (line.compare(0, 8, "#define ") == 0) {
            std::istringstream w(line.substr(8));
            w >> name >> value;
        } else if (line.compare(0, 10, "constexpr ") == 0 || line.compare(0, 12, "const float ") == 0 ||
                   line.compare(0, 10, "const int ") == 0) {
            const std::size_t eq = line.find('='), semi = line.find(';');
            if (eq == std::string::npos || semi == std::string::npos || semi < eq) continue;
            const std::string lhs = trim(line.substr(0, eq));
            name = lhs.substr(lhs.find_last_of(" \t") + 1);
            value = trim(line.substr(eq + 1, semi - eq - 1));
        } else {
            continue;
        }
        if (name.empty() || value.empty()) continue;
        if (scan_literal(value, 0, lit) == value.size() && !lit.empty()) out[name] = lit;
    }
    return out;
}

// Whole-word identifiers replaced by their constants' literals.
std::string substitute(const std::string& code, const std::map<std::string, std::string>& names) {
    std::string out;
    for (std::size_t i = 0; i < code.size();) {
        if (ident_char(code[i]) && (i == 0 || !ident_char(code[i - 1]))) {
            std::size_t j = i;
            while (j < code.size() && ident_char(code[j])) ++j;
            const std::string word = code.substr(i, j - i);
            const auto it = names.find(word);
            out += it != names.end() ? it->second : word;
            i = j;
        } else {
            out += code[i++];
        }
    }
    return out;
}

// The body ({...}) of the definition of function `name` (the first occurrence followed by a body).
std::string function_body(const std::string& code, const std::string& name) {
    for (std::size_t at = code.find(name); at != std::string::npos; at = code.find(name, at + 1)) {
        if ((at > 0 && ident_char(code[at - 1])) || (at + name.size() < code.size() && ident_char(code[at + name.size()]))) continue;
        std::size_t i = at + name.size();
        while (i < code.size() && std::isspace(static_cast<unsigned char>(code[i]))) ++i;
        if (i >= code.size() || code[i] != '(') continue;
        ++i;
        for (int depth = 1; i < code.size() && depth > 0; ++i) depth += code[i] == '(' ? 1 : code[i] == ')' ? -1 : 0;
        while (i < code.size() && (std::isspace(static_cast<unsigned char>(code[i])) || code.compare(i, 5, "const") == 0))
            i += code.compare(i, 5, "const") == 0 ? 5 : 1;
        if (i >= code.size() || code[i] != '{') continue;
        const std::size_t begin = i;
        for (int depth = 0; i < code.size(); ++i) {
            depth += code[i] == '{' ? 1 : code[i] == '}' ? -1 : 0;
            if (depth == 0) return code.substr(begin, i + 1 - begin);
        }
    }
    return std::string();
}

struct Twin {
    const char* glsl;
    const char* cpp;
};

// prefiltered_shadow: the GLSL port of the header's filter maths (glsl/prefiltered_shadow.glsl).
const Twin kPrefilteredTwins[] = {
    {"sk_pf_depth", "pf_clamp_depth"},                 // NaN -> 1, clamped to [0, 1]
    {"sk_pf_clamp", "pf_clamp"},
    {"sk_vsm_moments", "prefilter_vsm_moments"},
    {"sk_msm_moments", "prefilter_msm_moments"},
    {"sk_msm_quantize", "prefilter_msm_quantize"},     // Peters & Klein 2015 4.3: matrix and offset
    {"sk_msm_dequantize", "prefilter_msm_dequantize"}, // its inverse
    {"sk_pf_chebyshev", "pf_chebyshev"},
    {"sk_pf_vsm_bound", "pf_vsm_bound"},               // the float cancellation term 3 u, 4 u
    {"sk_pf_linstep", "pf_linstep"},
    {"sk_pf_msm_root_tolerance", "pf_msm_root_tolerance"},
    {"sk_pf_msm_one_depth_variance", "pf_msm_one_depth_variance"},
    {"sk_pf_two_depths_shadow", "pf_two_depths_shadow"},
    {"sk_msm_visibility", "prefilter_msm"},            // non-finite moments or NaN t -> 1 (lit)
    {"sk_prefilter_receiver_bias", "prefilter_receiver_bias"},
    {"sk_prefilter_soft_width", "prefilter_soft_width"},
    {"sk_prefilter_receiver_slope", "prefilter_receiver_slope"},
    {"sk_prefilter_depth_from_window", "prefilter_depth_from_window"},
};

// The printed literal equals x to its last printed digit (half a unit of it).
bool matches_to_printed_digits(const std::string& lit, double x) {
    const double v = std::strtod(lit.c_str(), nullptr);
    const std::size_t e = lit.find_first_of("eE");
    const std::string mant = lit.substr(0, e);
    const std::size_t dot = mant.find('.');
    const int decimals = dot == std::string::npos ? 0 : int(mant.size() - dot - 1);
    const int exp10 = e == std::string::npos ? 0 : std::atoi(lit.c_str() + e + 1);
    return std::fabs(v - x) <= 0.5 * std::pow(10.0, exp10 - decimals) * (1.0 + 1e-9);
}

int significant_digits(const std::string& lit) {
    const std::string mant = lit.substr(0, lit.find_first_of("eE"));
    std::string digits;
    for (char c : mant)
        if (c != '.') digits += c;
    const std::size_t first = digits.find_first_not_of('0');
    if (first == std::string::npos) return 0;
    digits = digits.substr(first);
    if (mant.find('.') != std::string::npos) {
        const std::size_t last = digits.find_last_not_of('0');
        digits = digits.substr(0, last + 1);
    }
    return int(digits.size());
}

}  // namespace

TEST_CASE("glsl twins: prefiltered_shadow.glsl functions carry the header's constants and fallbacks") {
    const std::string glsl = strip_comments(read_source("glsl/prefiltered_shadow.glsl"));
    const std::string hpp = strip_comments(read_source("include/shadowkit/prefiltered_shadow.hpp"));
    const auto gnames = named_constants(glsl), hnames = named_constants(hpp);
    CHECK(hnames.count("kPrefilterMsmOffset") == 1);  // the parser finds the header's named constants
    std::size_t compared = 0;
    for (const Twin& t : kPrefilteredTwins) {
        const std::string gb = function_body(glsl, t.glsl), hb = function_body(hpp, t.cpp);
        REQUIRE_MESSAGE(!gb.empty(), t.glsl << " not found in the snippet");
        REQUIRE_MESSAGE(!hb.empty(), t.cpp << " not found in the header");
        const std::vector<std::string> gl = literals(substitute(gb, gnames)), hl = literals(substitute(hb, hnames));
        const std::string what = std::string(t.glsl) + " {" + join(gl) + "} vs " + t.cpp + " {" + join(hl) + "}";
        INFO(what);
        CHECK(values(gl) == values(hl));
        CHECK(operators(substitute(gb, gnames)) == operators(substitute(hb, hnames)));
        compared += gl.size();
    }
    CHECK(compared > 60);  // the quantization matrices alone are 34 literals
    // the exponent limits: named in both, equal, and the largest exponent whose exp stays finite in float
    for (const char* name : {"pf_max_esm_exponent", "pf_max_evsm_exponent"}) REQUIRE(hnames.count(name) == 1);
    const double esm = std::strtod(hnames.at("pf_max_esm_exponent").c_str(), nullptr);
    const double evsm = std::strtod(hnames.at("pf_max_evsm_exponent").c_str(), nullptr);
    const std::vector<double> gl_esm = values(literals(function_body(glsl, "sk_esm_moment")));
    const std::vector<double> gl_evsm = values(literals(function_body(glsl, "sk_evsm_moments")));
    CHECK(std::count(gl_esm.begin(), gl_esm.end(), esm) == 1);
    CHECK(std::count(gl_evsm.begin(), gl_evsm.end(), evsm) == 2);
    CHECK(esm <= std::log(double(FLT_MAX)));
    CHECK(esm > std::log(double(FLT_MAX)) - 1e-5);
    CHECK(evsm <= 0.5 * std::log(double(FLT_MAX)));
    CHECK(evsm > 0.5 * std::log(double(FLT_MAX)) - 1e-5);
    CHECK(std::isfinite(std::exp(float(esm))));
    CHECK(std::isfinite(std::exp(float(evsm)) * std::exp(float(evsm))));
}

TEST_CASE("glsl twins: every computed constant of a snippet is its header's, a closed form, or listed GLSL-only") {
    const double pi = 3.14159265358979323846;
    const double closed_forms[] = {pi, 2.0 * pi, 0.5 * pi, 1.0 / (2.0 * pi), 1.0 / pi, double(FLT_MAX),
                                   std::log(double(FLT_MAX)), 0.5 * std::log(double(FLT_MAX)), std::sqrt(1.0 / 3.0)};
    // GLSL-only, with the reason they have no twin in the header:
    const std::set<std::pair<std::string, std::string>> glsl_only = {
        // interleaved gradient noise (Jimenez 2014): a per-pixel hash of the snippets, no CPU counterpart
        {"contact_shadow.glsl", "52.9829189"}, {"contact_shadow.glsl", "0.06711056"}, {"contact_shadow.glsl", "0.00583715"},
        {"pcss.glsl", "52.9829189"}, {"pcss.glsl", "0.06711056"}, {"pcss.glsl", "0.00583715"},
    };
    const char* snippets[] = {"cascades", "contact_shadow", "linear_light", "omni_shadow", "pcss", "penumbra_wedge",
                              "perspective_shadow_maps", "prefiltered_shadow", "prt", "shadow_cache", "shadow_volume",
                              "silhouette_map", "smoothie"};
    int checked = 0, in_header = 0;
    for (const char* name : snippets) {
        const std::string file = std::string(name) + ".glsl";
        std::string glsl = strip_comments(read_source("glsl/" + file));
        if (std::string(name) == "pcss") {
            // the 64 Poisson points are poisson_disk.hpp's output (the comment above the array says
            // how), not constants of pcss.hpp: left out here
            const std::size_t a = glsl.find("sk_poisson_disk64[64] = vec2[64](");
            REQUIRE(a != std::string::npos);
            glsl.erase(a, glsl.find(");", a) - a);
        }
        const std::vector<double> header = values(literals(strip_comments(read_source("include/shadowkit/" + std::string(name) + ".hpp"))));
        for (const std::string& lit : literals(glsl)) {
            if (significant_digits(lit) < 6) continue;
            ++checked;
            const double v = std::strtod(lit.c_str(), nullptr);
            bool ok = std::find(header.begin(), header.end(), v) != header.end();
            in_header += ok ? 1 : 0;
            for (double c : closed_forms) ok = ok || matches_to_printed_digits(lit, c);
            ok = ok || glsl_only.count({file, lit}) == 1;
            const std::string what = file + ": " + lit;
            INFO(what);
            CHECK(ok);
        }
    }
    MESSAGE(checked, " computed constants in the snippets, ", in_header, " of them in their headers");
    CHECK(in_header > 34);
}

namespace {
// The value of `#define NAME VALUE` in a snippet (an integer, decimal or hex with a u suffix); -1 if absent.
long long glsl_define(const std::string& glsl, const std::string& name) {
    std::istringstream in(glsl);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream w(trim(line));
        std::string d, n, v;
        w >> d >> n >> v;
        if (d == "#define" && n == name && !v.empty()) return std::strtoll(v.c_str(), nullptr, 0);
    }
    return -1;
}
// The integer initializer of `constexpr <type> NAME = VALUE;` in a header (hex, decimal, or `1 << k`).
long long header_constant(const std::string& hpp, const std::string& name) {
    const std::size_t a = hpp.find(" " + name + " = ");
    if (a == std::string::npos) return -1;
    const std::string v = trim(hpp.substr(a + name.size() + 4, hpp.find(';', a) - a - name.size() - 4));
    return std::strtoll(v.c_str(), nullptr, 0);
}
}  // namespace

TEST_CASE("glsl twins: virtual_shadow_map.glsl has the header's page-table bits, level limit and GPU block layout") {
    const std::string glsl = strip_comments(read_source("glsl/virtual_shadow_map.glsl"));
    const std::string hpp = strip_comments(read_source("include/shadowkit/virtual_shadow_map.hpp"));
    CHECK(glsl_define(glsl, "SK_VSM_MAX_LEVELS") == header_constant(hpp, "kVsmMaxLevels"));
    CHECK(glsl_define(glsl, "SK_VSM_PAGE_VALID") == header_constant(hpp, "kVsmPageValid"));
    CHECK(glsl_define(glsl, "SK_VSM_SLOT_MASK") == header_constant(hpp, "kVsmSlotMask"));
    CHECK(header_constant(hpp, "kVsmPageValid") == 0x80000000LL);
    // std430 size of SkVsmData's members before the page table (mat4 64 bytes, ivec4 / vec4 16, arrays
    // of SK_VSM_MAX_LEVELS) = vsm_gpu_block's header words * 4
    const std::size_t a = glsl.find("buffer SkVsmData {"), b = glsl.find("};", a);
    REQUIRE(a != std::string::npos);
    std::istringstream in(glsl.substr(a, b - a));
    std::string line;
    long long bytes = 0;
    int members = 0;
    bool runtime_array = false;
    while (std::getline(in, line)) {
        std::istringstream w(trim(line));
        std::string type, name;
        w >> type >> name;
        const long long size = type == "mat4" ? 64 : (type == "ivec4" || type == "vec4") ? 16 : type == "uint" ? 4 : 0;
        if (size == 0) continue;
        ++members;
        if (name.find("[]") != std::string::npos) { runtime_array = true; break; }
        const std::size_t br = name.find('[');
        long long count = 1;
        if (br != std::string::npos) {
            const std::string c = name.substr(br + 1, name.find(']') - br - 1);
            count = c == "SK_VSM_MAX_LEVELS" ? glsl_define(glsl, c) : std::strtoll(c.c_str(), nullptr, 10);
        }
        bytes += size * count;
    }
    CHECK(members == 6);
    CHECK(runtime_array);
    const std::size_t at = hpp.find("kVsmGpuHeaderWords = ");
    REQUIRE(at != std::string::npos);
    // the header's expression is 16 * 16 + 16 * 4 + 4 + 4 + 4: evaluate it by its terms
    long long words = 0;
    std::istringstream e(hpp.substr(at + 21, hpp.find(';', at) - at - 21));
    std::string tok, prev;
    long long term = 1;
    bool mul = false;
    while (e >> tok) {
        if (tok == "+") { words += term; term = 1; continue; }
        if (tok == "*") { mul = true; continue; }
        term = mul ? term * std::strtoll(tok.c_str(), nullptr, 10) : std::strtoll(tok.c_str(), nullptr, 10);
        mul = false;
    }
    words += term;
    CHECK(bytes == words * 4);
    CHECK(words == 332);
}

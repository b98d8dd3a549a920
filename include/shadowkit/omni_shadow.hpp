// shadowkit/omni_shadow.hpp - omnidirectional (point-light) shadow maps: cube maps and
// dual-paraboloid maps.
//
// What is here:
//   * cube maps: the six 90-degree face view-projections sharing one near plane (GL or zero-to-one
//     clip depth, reversed-Z, far at infinity), in the face orientation of the GL cube-map
//     convention so that rendering face f with view_proj[f] into GL_TEXTURE_CUBE_MAP_POSITIVE_X + f
//     gives the texture a cube lookup expects; face selection for a direction (every direction maps
//     to exactly one face, ties resolved as documented at omni_cube_face) and its inverse;
//   * linear distance-to-light storage (stored = distance / range) and its receiver-side bias,
//     derived from the texel footprint and the storage format (omni_distance_bias);
//   * per-face caster culling: a caster box or sphere that does not intersect a face's frustum
//     (exact separating-axis / closest-point tests, in double) is left out of that face; output as
//     per-caster face bitmasks or per-face index lists, in caller buffers, with the saved draws;
//   * dual-paraboloid maps (Brabec, Annen & Seidel 2002): projection of a direction, its inverse
//     (which continues across the rim into the other hemisphere, for filtering across the seam),
//     and the tessellation-error bound: the largest deviation, in texels, between the curved
//     paraboloid image of a straight edge and the straight edge the rasterizer draws.
//
// Usage (cube map):
//   namespace sk = shadowkit;
//   sk::OmniCubeInput in;
//   in.light_position = glm::vec4(light_pos, 1.0f);           // a point light (w > 0)
//   in.near_z = 0.01f; in.far_z = range;
//   sk::OmniCubeMatrices cm = sk::omni_cube_matrices(in);      // cm.view_proj[0..5]
//   if (cm.status != sk::Status::Ok) ...                       // see "Limits" below
//   sk::OmniCullInput ci; ci.light_position = in.light_position; ci.near_z = in.near_z; ci.far_z = in.far_z;
//   ci.boxes = boxes; ci.box_count = n;                        // 6 floats per box: min xyz, max xyz
//   std::vector<uint32_t> lists(6 * n); size_t off[7];
//   sk::OmniCullResult cr = sk::omni_cull_face_lists(ci, lists.data(), lists.size(), off);
//   for face f: attach GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, draw casters lists[off[f] .. off[f+1])
//   with cm.view_proj[f], writing gl_FragDepth = distance / range (glsl/omni_shadow.glsl).
//   Lookup: sk_cube_visibility_distance(..., bias) with bias from omni_distance_bias (or its GLSL twin).
// Usage (dual paraboloid):
//   sk::OmniParaboloidFrame fr = sk::omni_paraboloid_frame(light_position, axis, up);  // fr.view
//   float L = sk::omni_paraboloid_max_edge_length(distance, size, 1.0f).length;        // tessellate to L
//   two passes (front, back) with sk_dp_clip_position(...) in the vertex stage.
//
// Conventions.
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
//   Omnidirectional maps are for point lights only: a directional light (w = 0) has no position to
//   put the cube or the paraboloids at and is rejected with Status::InvalidLight as well (use a
//   directional shadow map). The light's position is xyz / w, evaluated in double.
//   * Units: world units (wu) for positions, distances, near/far and biases; radians for angles;
//     texels for filter radii and tessellation errors.
//   * Clip depth: ClipDepth (GL [-1, 1] or zero-to-one) plus reversed_z, far = +inf allowed.
//     Limits (omni_cube_matrices): the float matrix must map the near plane and the far plane to
//     their NDC depths within 1e-4 (GL: -1 and +1; zero-to-one: 0 and 1; reversed: swapped), else
//     Status::Overflow: far must exceed near by more than about 0.12% (far / near > 1.0012); near
//     1, far 1 + 1 ulp is rejected (the old code mapped its near plane to NDC -2).
//   * Cube faces: GL order and orientation (OpenGL 4.6 sec. 8.13); face f renders into
//     GL_TEXTURE_CUBE_MAP_POSITIVE_X + f.
//   * Buffers: every output buffer is a pointer + capacity in elements of the pointer's type;
//     results say `count` (elements written) and `needed` (elements the whole output needs).
//     Nothing here allocates.
//   * Results: every validating function returns a struct whose first member is `status`; `Ok` only
//     with finite outputs in their documented ranges. A non-Ok result's `detail` names the offending
//     input and the rule ("near_z: not > 0"), a static string; nullptr when Ok.
//
// Based on:
//   Gerasimov 2004, "Omnidirectional Shadow Mapping", GPU Gems ch. 12 (cube shadow maps storing
//     the distance to the light).
//   Brabec, Annen & Seidel 2002, "Shadow Mapping for Hemispherical and Omnidirectional Light
//     Sources", CGI 2002 (dual-paraboloid shadow maps; the paraboloid f(x,y) = 1/2 - (x^2+y^2)/2
//     of Heidrich & Seidel 1998, "View-independent environment maps").
//   OpenGL 4.6 core specification, sec. 8.13 "Cube Map Texture Selection" (face table).
//   Moschig, "Apelles" thesis, sec. 2.1.5 and 3.3 (omnidirectional shadows, linear depth metric).
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace shadowkit {

#ifndef SHADOWKIT_STATUS_DEFINED
#define SHADOWKIT_STATUS_DEFINED
/// shadowkit's release, major * 10000 + minor * 100 + patch (0.1.0), the same in every header. Whichever
/// header comes first defines this block; a header of another release included with it stops the
/// build (the #error after the block) instead of mixing two definitions silently.
#define SHADOWKIT_VERSION 100
/// Outcome of a shadowkit call: one set for every header. `Ok` is the only success. A result that no
/// call has filled says `NotRun`. What a successful call found (no blocker, a fallback, nothing
/// visible, an edge to skip) is a field of its result, never a status.
enum class Status : std::uint8_t {
    NotRun,            ///< a default-constructed result: no call has filled it
    Ok,                ///< success: every output is finite and means what its comment says
    InvalidArgument,   ///< a value outside its documented range (null pointer with a count, size 0, near >= far, ...)
    NonFinite,         ///< NaN or Inf in an input
    IndexOutOfRange,   ///< a mesh index >= the vertex count
    InvalidLight,      ///< light position NaN/Inf, w < 0, or (0, 0, 0, 0)
    BufferTooSmall,    ///< an output buffer is too small; the result's `needed` says how many elements
    Overflow,          ///< finite input whose result is not representable (beyond float, depth steps collapse)
    LightInsideVolume  ///< a point light inside the receivers' bounds: no single frustum holds them (use a cube map)
};
/// The enumerator's name, for logs and test messages.
inline const char* status_name(Status s) {
    switch (s) {
    case Status::NotRun: return "NotRun";
    case Status::Ok: return "Ok";
    case Status::InvalidArgument: return "InvalidArgument";
    case Status::NonFinite: return "NonFinite";
    case Status::IndexOutOfRange: return "IndexOutOfRange";
    case Status::InvalidLight: return "InvalidLight";
    case Status::BufferTooSmall: return "BufferTooSmall";
    case Status::Overflow: return "Overflow";
    case Status::LightInsideVolume: return "LightInsideVolume";
    }
    return "?";
}
#endif
#if !defined(SHADOWKIT_VERSION) || SHADOWKIT_VERSION != 100
#error "shadowkit: headers of two releases included together (this one is 0.1.0, SHADOWKIT_VERSION 100); vendor the headers of one release"
#endif
#ifndef SHADOWKIT_CLIP_DEPTH_DEFINED
#define SHADOWKIT_CLIP_DEPTH_DEFINED
/// Clip-space depth range of the projection: OpenGL [-1,1] or D3D/Vulkan/glClipControl [0,1].
enum class ClipDepth { NegativeOneToOne, ZeroToOne };
#endif
#ifndef SHADOWKIT_DEPTH_FORMAT_DEFINED
#define SHADOWKIT_DEPTH_FORMAT_DEFINED
/// Depth-buffer storage format.
enum class DepthFormat { Float32, Fixed24, Fixed16 };
#endif

/// Cube faces in GL order: face index f is GL_TEXTURE_CUBE_MAP_POSITIVE_X + f.
enum class OmniCubeFace : std::uint8_t { PositiveX = 0, NegativeX, PositiveY, NegativeY, PositiveZ, NegativeZ };

/// Bitmask with every face set (bit f = face f).
constexpr std::uint8_t omni_all_faces_mask = 0x3F;

// ------------------------------------------------------------------------------------ cube faces

/// Orthonormal basis of a face: `forward` is the major axis, `right` the direction of increasing
/// texture s and `up` of increasing t (GL cube-map table), right = cross(forward, up).
struct OmniFaceBasis {
    glm::vec3 forward{1.0f, 0.0f, 0.0f};
    glm::vec3 right{0.0f, 0.0f, -1.0f};
    glm::vec3 up{0.0f, -1.0f, 0.0f};
};

/// Face basis of the GL convention (OpenGL 4.6 sec. 8.13: +X: s = -z, t = -y; -X: s = +z, t = -y;
/// +Y: s = +x, t = +z; -Y: s = +x, t = -z; +Z: s = +x, t = -y; -Z: s = -x, t = -y).
/// A face value outside the enum gives the +X basis.
inline OmniFaceBasis omni_cube_face_basis(OmniCubeFace face) {
    OmniFaceBasis b;
    switch (face) {
        case OmniCubeFace::NegativeX: b = {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}}; break;
        case OmniCubeFace::PositiveY: b = {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}}; break;
        case OmniCubeFace::NegativeY: b = {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}}; break;
        case OmniCubeFace::PositiveZ: b = {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}}; break;
        case OmniCubeFace::NegativeZ: b = {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}}; break;
        default: b = {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}}; break;
    }
    return b;
}

/// Input of omni_cube_matrices.
struct OmniCubeInput {
    /// The point light (w > 0; see "Lights" in the header comment) (required: the default
    /// (0, 0, 0, 0) is rejected with InvalidLight; w = 0 too).
    glm::vec4 light_position{0.0f};
    float near_z = 0.05f;        ///< [Units: wu] [Limit: > 0, finite] shared near plane (distance along the face axis)
    float far_z = 100.0f;        ///< [Units: wu] [Limit: far / near > ~1.0012 (see Limits), +inf allowed] shared far plane
    ClipDepth clip_depth = ClipDepth::NegativeOneToOne;
    bool reversed_z = false;     ///< near -> 1, far -> 0 (with ZeroToOne: the float-friendly choice)
};

/// The six face matrices of a cube shadow map.
struct OmniCubeMatrices {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::mat4 proj{1.0f};        ///< shared 90-degree, aspect-1 perspective
    glm::mat4 view[6];           ///< world -> face view (looks down -z; x = right, y = up of the basis)
    glm::mat4 view_proj[6];      ///< proj * view[f]
};

namespace detail {

inline bool omni_finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

inline bool omni_valid_range(float n, float f, bool allow_inf_far) {
    if (!std::isfinite(n) || !(n > 0.0f)) return false;
    if (std::isnan(f) || !(f > n)) return false;
    if (std::isinf(f) && !allow_inf_far) return false;
    return true;
}

// Status of a near / far pair (far = +inf allowed): NaN or an infinite near -> NonFinite, near <= 0,
// far <= near or far = -inf -> InvalidArgument.
// `why` receives where a non-Ok status came from (a static string).
inline Status omni_range_status(float n, float f, const char*& why) {
    if (std::isnan(n) || std::isnan(f) || std::isinf(n)) {
        why = std::isnan(f) ? "far_z: NaN" : "near_z: NaN or Inf";
        return Status::NonFinite;
    }
    if (!(n > 0.0f) || !(f > n)) {
        why = !(n > 0.0f) ? "near_z: not > 0" : "far_z: not > near_z";
        return Status::InvalidArgument;
    }
    return Status::Ok;
}

// The point light's position xyz / w (double): InvalidLight for NaN/Inf, w <= 0 (a directional
// light has no position) and (0, 0, 0, 0); Overflow when xyz / w is beyond float.
inline Status omni_point_light(const glm::vec4& L, glm::dvec3& center, const char*& why) {
    if (!std::isfinite(L.x) || !std::isfinite(L.y) || !std::isfinite(L.z) || !std::isfinite(L.w) || !(L.w > 0.0f)) {
        why = !std::isfinite(L.x) || !std::isfinite(L.y) || !std::isfinite(L.z) || !std::isfinite(L.w)
                  ? "light_position: NaN or Inf"
                  : (L.w == 0.0f ? "light_position: w = 0 (directional; a point light is needed)" : "light_position: w < 0");
        return Status::InvalidLight;
    }
    const double w = L.w;
    center = glm::dvec3(L.x / w, L.y / w, L.z / w);
    const double fmax = static_cast<double>(std::numeric_limits<float>::max());
    if (!(std::fabs(center.x) <= fmax && std::fabs(center.y) <= fmax && std::fabs(center.z) <= fmax)) {
        why = "light_position: xyz / w beyond float";
        return Status::Overflow;
    }
    return Status::Ok;
}
inline Status omni_point_light(const glm::vec4& L, glm::dvec3& center) {
    const char* why = nullptr;
    return omni_point_light(L, center, why);
}

inline bool omni_finite_mat(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// Local face coordinates (t along the face axis, u along right, v along up) of a world offset.
inline void omni_to_face(int face, double x, double y, double z, double& t, double& u, double& v) {
    switch (face) {
        case 0: t = x; u = -z; v = -y; break;
        case 1: t = -x; u = z; v = -y; break;
        case 2: t = y; u = x; v = z; break;
        case 3: t = -y; u = x; v = -z; break;
        case 4: t = z; u = x; v = -y; break;
        default: t = -z; u = -x; v = -y; break;
    }
}

// A box in face coordinates stays a box (the map is a signed permutation).
inline void omni_box_to_face(int face, const double lo[3], const double hi[3], double tl[3], double th[3]) {
    // components: 0 = t, 1 = u, 2 = v; each is +/- one world axis
    static constexpr int axis[6][3] = {{0, 2, 1}, {0, 2, 1}, {1, 0, 2}, {1, 0, 2}, {2, 0, 1}, {2, 0, 1}};
    static constexpr int sign[6][3] = {{1, -1, -1}, {-1, 1, -1}, {1, 1, 1}, {-1, 1, -1}, {1, 1, -1}, {-1, -1, -1}};
    for (int k = 0; k < 3; ++k) {
        const int a = axis[face][k];
        if (sign[face][k] > 0) {
            tl[k] = lo[a];
            th[k] = hi[a];
        } else {
            tl[k] = -hi[a];
            th[k] = -lo[a];
        }
    }
}

// Separation "a < b" with a relative slack that only ever keeps (never culls) borderline casters.
inline bool omni_less_sep(double a, double b) {
    const double slack = 1e-12 * (std::fabs(a) + std::fabs(b)) + 1e-300;
    return a < b - slack;
}

// Exact box-vs-face-frustum test: the frustum is {n <= t <= f, |u| <= t, |v| <= t}. Separating axes
// of two convex polyhedra: the box axes (t, u, v), the four side planes (t -+ u, t -+ v) and the
// cross products of box edges with the frustum's lateral edges (1, +-1, +-1): the axes u +- v.
inline bool omni_box_meets_face(const double tl[3], const double th[3], double n, double f) {
    const bool inf = std::isinf(f);
    if (omni_less_sep(th[0], n)) return false;                     // entirely before the near plane
    if (!inf && omni_less_sep(f, tl[0])) return false;              // beyond the far plane
    if (omni_less_sep(th[0], tl[1]) || omni_less_sep(th[0], -th[1])) return false;  // t - u < 0 or t + u < 0
    if (omni_less_sep(th[0], tl[2]) || omni_less_sep(th[0], -th[2])) return false;  // t - v < 0 or t + v < 0
    if (!inf) {
        if (omni_less_sep(f, tl[1]) || omni_less_sep(th[1], -f)) return false;        // |u| <= f
        if (omni_less_sep(f, tl[2]) || omni_less_sep(th[2], -f)) return false;        // |v| <= f
        if (omni_less_sep(2.0 * f, tl[1] + tl[2]) || omni_less_sep(th[1] + th[2], -2.0 * f)) return false;  // u + v
        if (omni_less_sep(2.0 * f, tl[1] - th[2]) || omni_less_sep(th[1] - tl[2], -2.0 * f)) return false;  // u - v
    }
    return true;
}

// Exact sphere-vs-face-frustum test: squared distance from (T, U, V) to the frustum is
// min over t in [n, f] of (t - T)^2 + max(|U| - t, 0)^2 + max(|V| - t, 0)^2, a convex piecewise
// quadratic in t; each piece's minimiser is (T + sum of active |U|, |V|) / (1 + active count).
inline bool omni_sphere_meets_face(double T, double U, double V, double r, double n, double f) {
    const double a = std::fabs(U), b = std::fabs(V);
    const double cuts[4] = {n, std::min(a, b), std::max(a, b), f};
    auto g = [&](double t) {
        const double da = std::max(a - t, 0.0), db = std::max(b - t, 0.0);
        return (t - T) * (t - T) + da * da + db * db;
    };
    double best = g(n);
    for (int k = 0; k < 3; ++k) {
        const double lo = std::max(cuts[k], n), hi = std::min(cuts[k + 1], f);
        if (!(lo <= hi)) continue;
        // on (lo, hi) the active terms are the |U|, |V| at or above hi (cut points are piece ends)
        double sum = T;
        int cnt = 1;
        if (a >= hi && a > lo) { sum += a; ++cnt; }
        if (b >= hi && b > lo) { sum += b; ++cnt; }
        best = std::min(best, g(std::clamp(sum / cnt, lo, hi)));
    }
    const double r2 = r * r;
    return best <= r2 + 1e-12 * (r2 + T * T + U * U + V * V) + 1e-300;
}

}  // namespace detail

/// The six face matrices. Every face uses proj = 90-degree symmetric perspective (aspect 1) with
/// the given near/far and depth convention; view[f] looks along omni_cube_face_basis(f).forward with
/// x = right and y = up, so window x grows with texture s and window y with t when rendering into
/// GL_TEXTURE_CUBE_MAP_POSITIVE_X + f. Far may be +inf (the limit projection, Everitt & Kilgard).
/// Statuses: InvalidLight (not a point light: w <= 0, NaN/Inf, (0, 0, 0, 0)); NonFinite (near NaN or
/// Inf, far NaN); InvalidArgument (near <= 0, far <= near); Overflow (the light's xyz / w or a
/// matrix entry beyond float, or near and far so close that the float matrix cannot map them to
/// their NDC depths within 1e-4: far / near <= ~1.0012; see "Limits" in the header comment).
inline OmniCubeMatrices omni_cube_matrices(const OmniCubeInput& in) {
    OmniCubeMatrices out;
    glm::dvec3 center;
    out.status = detail::omni_point_light(in.light_position, center, out.detail);
    if (out.status != Status::Ok) return out;
    out.status = detail::omni_range_status(in.near_z, in.far_z, out.detail);
    if (out.status != Status::Ok) return out;
    out.status = Status::NotRun;
    const double n = in.near_z, f = in.far_z;
    const bool inf = std::isinf(in.far_z);
    // z_clip = A z_view + B, w_clip = -z_view; ndc(d) at view distance d = -z_view.
    double A = 0.0, B = 0.0;
    const bool zo = in.clip_depth == ClipDepth::ZeroToOne;
    if (zo && !in.reversed_z) {          // ndc = f (d - n) / (d (f - n))
        A = inf ? -1.0 : -f / (f - n);
        B = inf ? -n : -f * n / (f - n);
    } else if (zo) {                     // reversed: ndc = n (f - d) / (d (f - n)); infinite: n / d
        A = inf ? 0.0 : n / (f - n);
        B = inf ? n : f * n / (f - n);
    } else if (!in.reversed_z) {         // glFrustum: ndc = (f + n)/(f - n) - 2 f n / ((f - n) d)
        A = inf ? -1.0 : -(f + n) / (f - n);
        B = inf ? -2.0 * n : -2.0 * f * n / (f - n);
    } else {                             // GL reversed: ndc negated
        A = inf ? 1.0 : (f + n) / (f - n);
        B = inf ? 2.0 * n : 2.0 * f * n / (f - n);
    }
    glm::mat4 P(0.0f);
    P[0][0] = 1.0f;  // cot(45 deg)
    P[1][1] = 1.0f;
    P[2][2] = static_cast<float>(A);
    P[3][2] = static_cast<float>(B);
    P[2][3] = -1.0f;
    if (!detail::omni_finite_mat(P)) {
        out.status = Status::Overflow;  // far so close to near that the depth scale is beyond float
        out.detail = "far_z: so close to near_z that the depth scale is beyond float";
        return out;
    }
    // Issue 19: with far within a few ulps of near the rounded A and B cancel (near 1, far 1 + 1 ulp
    // mapped the near plane to -2). The float matrix must map near and far to their NDC depths.
    {
        const double zn = zo ? (in.reversed_z ? 1.0 : 0.0) : (in.reversed_z ? 1.0 : -1.0);
        const double zf = zo ? (in.reversed_z ? 0.0 : 1.0) : (in.reversed_z ? -1.0 : 1.0);
        const double a = static_cast<double>(P[2][2]), bb = static_cast<double>(P[3][2]);
        const double got_n = -a + bb / n;                 // ndc(d) = (-a d + b) / d
        const double got_f = inf ? -a : -a + bb / f;
        if (!(std::fabs(got_n - zn) <= 1e-4) || !(std::fabs(got_f - zf) <= 1e-4)) {
            out.status = Status::Overflow;
            out.detail = "far_z: within float steps of near_z (near and far map off their depths)";
            return out;
        }
    }
    out.proj = P;
    const glm::vec3 light(center);
    for (int face = 0; face < 6; ++face) {
        const OmniFaceBasis b = omni_cube_face_basis(static_cast<OmniCubeFace>(face));
        glm::mat4 V(1.0f);
        // rows: right, up, -forward; translation -R * light (exact: R is a signed permutation)
        for (int c = 0; c < 3; ++c) {
            V[c][0] = b.right[c];
            V[c][1] = b.up[c];
            V[c][2] = -b.forward[c];
        }
        V[3][0] = -glm::dot(b.right, light);
        V[3][1] = -glm::dot(b.up, light);
        V[3][2] = glm::dot(b.forward, light);
        out.view[face] = V;
        out.view_proj[face] = P * V;
    }
    for (const auto& m : out.view_proj)
        if (!detail::omni_finite_mat(m)) {
            out.status = Status::Overflow;  // light so far out that the translation overflows
            out.detail = "light_position: so far out that the view translation overflows";
            return out;
        }
    out.status = Status::Ok;
    return out;
}

/// Result of omni_cube_face.
struct OmniFaceHit {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    OmniCubeFace face = OmniCubeFace::PositiveX;
    glm::vec2 st{0.5f};  ///< GL cube texture coordinates on that face, in [0,1]^2
};

/// The face a direction (need not be unit length) is looked up in, and its (s, t).
/// Rule: the major axis is the component of largest magnitude; ties go to the earlier axis in the
/// order x, y, z (|x| >= |y| and |x| >= |z| -> X; else |y| >= |z| -> Y; else Z), the sign is that
/// of the major component (never zero for a non-zero direction). So every non-zero finite
/// direction has exactly one face, directions on a cube edge or corner go to the first axis, and
/// the face always contains the direction in its closed frustum (|s - 0.5|, |t - 0.5| <= 0.5).
/// Hardware may break ties differently; both faces hold the same texel row there.
/// NaN/Inf -> NonFinite, the zero vector -> InvalidArgument.
inline OmniFaceHit omni_cube_face(const glm::vec3& d) {
    OmniFaceHit h;
    if (!detail::omni_finite3(d)) {
        h.status = Status::NonFinite;
        h.detail = "d: NaN or Inf";
        return h;
    }
    const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    int axis;
    if (ax >= ay && ax >= az) axis = 0;
    else if (ay >= az) axis = 1;
    else axis = 2;
    const float major = d[axis];
    if (!(major != 0.0f)) {  // zero vector
        h.status = Status::InvalidArgument;
        h.detail = "d: zero vector";
        return h;
    }
    const int face = 2 * axis + (major > 0.0f ? 0 : 1);
    const OmniFaceBasis b = omni_cube_face_basis(static_cast<OmniCubeFace>(face));
    const double m = std::fabs(static_cast<double>(major));
    const double sc = glm::dot(glm::dvec3(b.right), glm::dvec3(d)), tc = glm::dot(glm::dvec3(b.up), glm::dvec3(d));
    // OpenGL 4.6 sec. 8.13: s = (sc / |ma| + 1) / 2, t = (tc / |ma| + 1) / 2
    h.st = glm::vec2(static_cast<float>(std::clamp(0.5 * (sc / m + 1.0), 0.0, 1.0)),
                     static_cast<float>(std::clamp(0.5 * (tc / m + 1.0), 0.0, 1.0)));
    h.face = static_cast<OmniCubeFace>(face);
    h.status = Status::Ok;
    return h;
}

/// A unit direction (omni_cube_direction, omni_paraboloid_unproject).
struct OmniDirection {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::vec3 direction{0.0f};  ///< unit length
};

/// Inverse of omni_cube_face: the unit direction through (s, t) of a face. st outside [0,1]^2 is
/// allowed (continues the face plane); NaN/Inf -> NonFinite, a face outside the enum ->
/// InvalidArgument.
inline OmniDirection omni_cube_direction(OmniCubeFace face, const glm::vec2& st) {
    OmniDirection r;
    if (static_cast<int>(face) > 5) {
        r.status = Status::InvalidArgument;
        r.detail = "face: outside OmniCubeFace";
        return r;
    }
    if (!std::isfinite(st.x) || !std::isfinite(st.y)) {
        r.status = Status::NonFinite;
        r.detail = "st: NaN or Inf";
        return r;
    }
    const OmniFaceBasis b = omni_cube_face_basis(face);
    const glm::dvec3 d = glm::dvec3(b.forward) + (2.0 * st.x - 1.0) * glm::dvec3(b.right) + (2.0 * st.y - 1.0) * glm::dvec3(b.up);
    r.direction = glm::vec3(glm::normalize(d));
    r.status = detail::omni_finite3(r.direction) ? Status::Ok : Status::Overflow;  // |st| near FLT_MAX
    r.detail = r.status == Status::Ok ? nullptr : "st: so large the direction is not finite";
    return r;
}

/// A scalar result of omni_shadow.hpp.
struct OmniValue {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float value = 0.0f;  ///< the quantity the function's comment names
};

/// Largest angle (radians) between the directions of two points one texel apart on a face of
/// `size` texels: the gnomonic face plane has Lipschitz constant 1 (reached at the face center),
/// so one texel (2 / size in the plane) subtends at most 2 / size. size 0 -> InvalidArgument.
inline OmniValue omni_cube_texel_angle(std::uint32_t size) {
    OmniValue v;
    if (size == 0) {
        v.status = Status::InvalidArgument;
        v.detail = "size: 0";
        return v;
    }
    v.value = 2.0f / static_cast<float>(size);
    v.status = Status::Ok;
    return v;
}

// ------------------------------------------------------------------------ linear distance + bias

/// Result of omni_linear_depth.
struct OmniDepthResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float value = 0.0f;  ///< what the depth texture holds: distance / range, clamped to [0,1], quantized
};

/// Linear distance storage: the depth pass writes gl_FragDepth = distance / range (Gerasimov 2004),
/// `range` >= every distance that matters (usually the far plane). Fixed formats round to
/// 1 / (2^bits - 1). Distances beyond the range (+inf included) clamp to 1 (compare "lit" with
/// GL_LEQUAL). range NaN/Inf or distance NaN -> NonFinite; range <= 0, distance < 0 or a format
/// outside the enum -> InvalidArgument.
inline OmniDepthResult omni_linear_depth(float distance, float range, DepthFormat format) {
    OmniDepthResult r;
    if (!std::isfinite(range) || std::isnan(distance)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(range) ? "range: NaN or Inf" : "distance: NaN";
        return r;
    }
    if (!(range > 0.0f) || distance < 0.0f ||
        (format != DepthFormat::Float32 && format != DepthFormat::Fixed24 && format != DepthFormat::Fixed16)) {
        r.status = Status::InvalidArgument;
        r.detail = !(range > 0.0f) ? "range: not > 0" : (distance < 0.0f ? "distance: < 0" : "format: unknown DepthFormat");
        return r;
    }
    double v = std::min(1.0, static_cast<double>(distance) / static_cast<double>(range));
    if (format == DepthFormat::Fixed24) v = std::nearbyint(v * 16777215.0) / 16777215.0;
    else if (format == DepthFormat::Fixed16) v = std::nearbyint(v * 65535.0) / 65535.0;
    r.value = static_cast<float>(v);
    r.status = Status::Ok;
    return r;
}

/// Input of omni_distance_bias.
struct OmniBiasInput {
    float distance = 1.0f;        ///< [Units: wu] [Limit: >= 0, finite] receiver's distance to the light
    float cos_theta = 1.0f;       ///< [Limit: [-1,1]] cos of the angle between the receiver normal and the direction to the light
    /// [Units: rad] [Limit: > 0, finite] omni_cube_texel_angle / omni_paraboloid_texel_angle (required:
    /// the default 0 is rejected with InvalidArgument)
    float texel_angle = 0.0f;
    /// [Units: texels] [Limit: >= 0] Euclidean distance from the lookup point to the farthest texel
    /// center the filter reads: 0.7072 nearest, 1.4143 hardware 2x2 (GL_LINEAR compare),
    /// (k + 1) * 1.4143 for a (2k+1)^2 grid of 2x2 taps one texel apart.
    float filter_radius = 1.41422f;
    /// [Units: wu] [Limit: > 0, finite] the divisor of the stored distance, usually the far plane
    /// (required: the default 0 is rejected with InvalidArgument)
    float range = 0.0f;
    DepthFormat format = DepthFormat::Float32;
    float max_angle = 1.4835299f; ///< [Units: rad] [Limit: (0, pi/2)] theta is clamped here (85 deg): grazing receivers
    float constant = 0.0f;        ///< [Units: wu] [Limit: >= 0] added as is (rasterizer/interpolation slack)
};

/// Result of omni_distance_bias.
struct OmniBiasResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float bias_world = 0.0f;    ///< [Units: wu] subtract from the receiver distance before comparing
    float bias_stored = 0.0f;   ///< bias_world / range (stored units, distance / range): subtract from the stored reference value
};

/// Receiver-side bias for linear distance storage. A planar receiver at distance d whose normal
/// makes angle theta with the direction to the light is stored, along a texel-center ray at angle
/// theta' from the normal, at d cos(theta) / cos(theta'). The filter reads texels whose rays are
/// within alpha = filter_radius * texel_angle of the lookup ray, so the smallest stored value is
/// at theta' = max(theta - alpha, 0), and the receiver stays lit iff
///   bias >= d (1 - cos(theta) / cos(max(theta - alpha, 0)))            (exact for a plane)
/// plus the storage error: Float32 4 ulp of d (2^-22 d, rounding of length and the divide),
/// Fixed24 2 range / (2^24 - 1), Fixed16 2 range / (2^16 - 1) (half a step of rounding, the float
/// conversion of the stored value, which is half a step again at 24 bits, and of the reference),
/// plus `constant`. theta is clamped to max_angle (receivers more grazing
/// than that may show acne; the alternative bias grows to d at 90 degrees).
/// NaN/Inf in a field -> NonFinite; a field outside its [Limit] (range or texel_angle 0 included)
/// -> InvalidArgument; a bias beyond float -> Overflow.
inline OmniBiasResult omni_distance_bias(const OmniBiasInput& in) {
    OmniBiasResult r;
    if (!std::isfinite(in.range) || !std::isfinite(in.distance) || !std::isfinite(in.cos_theta) ||
        !std::isfinite(in.texel_angle) || !std::isfinite(in.filter_radius) || !std::isfinite(in.max_angle) ||
        !std::isfinite(in.constant)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(in.range) ? "range: NaN or Inf"
                   : (!std::isfinite(in.distance) ? "distance: NaN or Inf"
                   : (!std::isfinite(in.cos_theta) ? "cos_theta: NaN or Inf"
                   : (!std::isfinite(in.texel_angle) ? "texel_angle: NaN or Inf"
                   : (!std::isfinite(in.filter_radius) ? "filter_radius: NaN or Inf"
                   : (!std::isfinite(in.max_angle) ? "max_angle: NaN or Inf" : "constant: NaN or Inf")))));
        return r;
    }
    if (!(in.range > 0.0f) || in.distance < 0.0f || std::fabs(in.cos_theta) > 1.0f || !(in.texel_angle > 0.0f) ||
        in.filter_radius < 0.0f || !(in.max_angle > 0.0f) || !(in.max_angle < 1.5707963f) || in.constant < 0.0f ||
        (in.format != DepthFormat::Float32 && in.format != DepthFormat::Fixed24 && in.format != DepthFormat::Fixed16)) {
        r.status = Status::InvalidArgument;
        r.detail = !(in.range > 0.0f) ? "range: not > 0"
                   : (in.distance < 0.0f ? "distance: < 0"
                   : (std::fabs(in.cos_theta) > 1.0f ? "cos_theta: outside [-1, 1]"
                   : (!(in.texel_angle > 0.0f) ? "texel_angle: not > 0"
                   : (in.filter_radius < 0.0f ? "filter_radius: < 0"
                   : (!(in.max_angle > 0.0f) || !(in.max_angle < 1.5707963f) ? "max_angle: outside (0, pi/2)"
                   : (in.constant < 0.0f ? "constant: < 0" : "format: unknown DepthFormat"))))));
        return r;
    }
    const double d = in.distance;
    const double theta = std::min(std::acos(static_cast<double>(std::max(in.cos_theta, 0.0f))), static_cast<double>(in.max_angle));
    const double alpha = static_cast<double>(in.filter_radius) * static_cast<double>(in.texel_angle);
    const double geometric = d * (1.0 - std::cos(theta) / std::cos(std::max(theta - alpha, 0.0)));
    double storage = 0.0;
    switch (in.format) {
        case DepthFormat::Fixed24: storage = 2.0 * static_cast<double>(in.range) / 16777215.0; break;
        case DepthFormat::Fixed16: storage = 2.0 * static_cast<double>(in.range) / 65535.0; break;
        default: storage = d * std::ldexp(1.0, -22); break;
    }
    const double b = std::max(0.0, geometric) + storage + static_cast<double>(in.constant);
    r.bias_world = static_cast<float>(b);
    r.bias_stored = static_cast<float>(b / static_cast<double>(in.range));
    if (!std::isfinite(r.bias_world) || !std::isfinite(r.bias_stored)) {
        r.status = Status::Overflow;
        r.detail = "bias_world: beyond float range";
        return r;
    }
    r.status = Status::Ok;
    return r;
}

// ---------------------------------------------------------------------------- per-face culling

/// Input of the per-face caster culling (omni_cull_casters, omni_cull_face_lists).
struct OmniCullInput {
    /// The point light (w > 0) the cube is rendered from (required: the default (0, 0, 0, 0) and
    /// w = 0 are rejected with InvalidLight).
    glm::vec4 light_position{0.0f};
    float near_z = 0.05f;         ///< the shared near plane of the faces (omni_cube_matrices)
    float far_z = 100.0f;         ///< the shared far plane (+inf allowed)
    /// `boxes` holds 6 * box_count floats: min x,y,z, max x,y,z of each caster box (null only with
    /// box_count 0).
    const float* boxes = nullptr;
    std::size_t box_count = 0;
    /// `spheres` holds 4 * sphere_count floats: center x,y,z, radius of each caster sphere; their
    /// caster indices follow the boxes (null only with sphere_count 0).
    const float* spheres = nullptr;
    std::size_t sphere_count = 0;
};

/// Result of omni_cull_casters / omni_cull_face_lists.
struct OmniCullResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;           ///< elements written to the output buffer (masks or list entries)
    std::size_t needed = 0;          ///< elements the output needs (masks: caster_count; lists: draws)
    std::size_t caster_count = 0;    ///< box_count + sphere_count
    std::size_t draws = 0;           ///< sum over faces of the casters drawn into it (= list entries needed)
    std::size_t draws_saved = 0;     ///< 6 * caster_count - draws
    std::size_t face_draws[6] = {0, 0, 0, 0, 0, 0};
    std::size_t invalid_count = 0;   ///< NaN/Inf, min > max or radius < 0: drawn into every face (never culled)
};

namespace detail {
// Mask of the faces a box [l, h] (relative to the light, double) meets.
inline std::uint8_t omni_box_mask_rel(const double l[3], const double h[3], float near_z, float far_z) {
    std::uint8_t mask = 0;
    for (int f = 0; f < 6; ++f) {
        double tl[3], th[3];
        omni_box_to_face(f, l, h, tl, th);
        if (omni_box_meets_face(tl, th, near_z, far_z)) mask = static_cast<std::uint8_t>(mask | (1u << f));
    }
    return mask;
}
inline std::uint8_t omni_sphere_mask_rel(double x, double y, double z, float radius, float near_z, float far_z) {
    std::uint8_t mask = 0;
    for (int f = 0; f < 6; ++f) {
        double t, u, v;
        omni_to_face(f, x, y, z, t, u, v);
        if (omni_sphere_meets_face(t, u, v, radius, near_z, far_z)) mask = static_cast<std::uint8_t>(mask | (1u << f));
    }
    return mask;
}
}  // namespace detail

/// Faces whose frustum {near <= t <= far, |u| <= t, |v| <= t} (face coordinates) a box meets:
/// exact separating-axis test in double (touching counts as meeting). Total: bad input (a light
/// that is not a point light, a bad range, NaN/Inf or min > max) gives all faces (never culls).
inline std::uint8_t omni_cube_box_mask(const glm::vec4& light_position, float near_z, float far_z, const glm::vec3& lo,
                                       const glm::vec3& hi) {
    glm::dvec3 c;
    if (detail::omni_point_light(light_position, c) != Status::Ok || !detail::omni_valid_range(near_z, far_z, true) ||
        !detail::omni_finite3(lo) || !detail::omni_finite3(hi) || lo.x > hi.x || lo.y > hi.y || lo.z > hi.z)
        return omni_all_faces_mask;
    const double l[3] = {double(lo.x) - c.x, double(lo.y) - c.y, double(lo.z) - c.z};
    const double h[3] = {double(hi.x) - c.x, double(hi.y) - c.y, double(hi.z) - c.z};
    return detail::omni_box_mask_rel(l, h, near_z, far_z);
}

/// Same for a sphere (exact closest-point distance to each face frustum). Total: bad input (also
/// radius NaN/Inf or < 0) gives all faces.
inline std::uint8_t omni_cube_sphere_mask(const glm::vec4& light_position, float near_z, float far_z,
                                          const glm::vec3& center, float radius) {
    glm::dvec3 c;
    if (detail::omni_point_light(light_position, c) != Status::Ok || !detail::omni_valid_range(near_z, far_z, true) ||
        !detail::omni_finite3(center) || !std::isfinite(radius) || radius < 0.0f)
        return omni_all_faces_mask;
    return detail::omni_sphere_mask_rel(double(center.x) - c.x, double(center.y) - c.y, double(center.z) - c.z, radius,
                                        near_z, far_z);
}

namespace detail {

inline bool omni_bad_box(const float* b) {
    for (int k = 0; k < 6; ++k)
        if (!std::isfinite(b[k])) return true;
    return b[0] > b[3] || b[1] > b[4] || b[2] > b[5];
}
inline bool omni_bad_sphere(const float* s) {
    for (int k = 0; k < 4; ++k)
        if (!std::isfinite(s[k])) return true;
    return s[3] < 0.0f;
}

// Validates the input; fills counts and calls emit(caster index, mask) in order.
template <class Emit>
OmniCullResult omni_cull(const OmniCullInput& in, Emit&& emit) {
    OmniCullResult r;
    glm::dvec3 c;
    r.status = omni_point_light(in.light_position, c, r.detail);
    if (r.status != Status::Ok) return r;
    r.status = omni_range_status(in.near_z, in.far_z, r.detail);
    if (r.status != Status::Ok) return r;
    r.status = Status::NotRun;
    const std::size_t max_count = std::numeric_limits<std::size_t>::max() / 8;
    if ((in.box_count && !in.boxes) || (in.sphere_count && !in.spheres) || in.box_count > max_count ||
        in.sphere_count > max_count || in.box_count + in.sphere_count > max_count) {
        r.status = Status::InvalidArgument;
        r.detail = in.box_count && !in.boxes ? "boxes: null with box_count > 0"
                   : (in.sphere_count && !in.spheres ? "spheres: null with sphere_count > 0" : "box_count + sphere_count: too many");
        return r;
    }
    r.caster_count = in.box_count + in.sphere_count;
    for (std::size_t i = 0; i < r.caster_count; ++i) {
        std::uint8_t m = omni_all_faces_mask;
        if (i < in.box_count) {
            const float* b = in.boxes + 6 * i;
            if (omni_bad_box(b)) {
                ++r.invalid_count;
            } else {
                const double l[3] = {double(b[0]) - c.x, double(b[1]) - c.y, double(b[2]) - c.z};
                const double h[3] = {double(b[3]) - c.x, double(b[4]) - c.y, double(b[5]) - c.z};
                m = omni_box_mask_rel(l, h, in.near_z, in.far_z);
            }
        } else {
            const float* s = in.spheres + 4 * (i - in.box_count);
            if (omni_bad_sphere(s)) ++r.invalid_count;
            else m = omni_sphere_mask_rel(double(s[0]) - c.x, double(s[1]) - c.y, double(s[2]) - c.z, s[3], in.near_z, in.far_z);
        }
        for (int f = 0; f < 6; ++f)
            if (m & (1u << f)) {
                ++r.face_draws[f];
                ++r.draws;
            }
        emit(i, m);
    }
    r.draws_saved = 6 * r.caster_count - r.draws;
    r.status = Status::Ok;
    return r;
}

}  // namespace detail

/// Per-caster face masks: `face_masks` holds `mask_capacity` uint8 elements; it needs
/// caster_count = box_count + sphere_count (`needed`); bit f of face_masks[i] set = draw caster i
/// into face f. Casters are the boxes, then the spheres. If mask_capacity < caster_count:
/// BufferTooSmall, the first mask_capacity masks written (`count`), all other counts complete.
/// face_masks null with mask_capacity > 0 -> InvalidArgument (null with 0: a size query).
inline OmniCullResult omni_cull_casters(const OmniCullInput& in, std::uint8_t* face_masks, std::size_t mask_capacity) {
    if (!face_masks && mask_capacity != 0) {
        OmniCullResult bad;
        bad.status = Status::InvalidArgument;
        bad.detail = "face_masks: null with mask_capacity > 0";
        return bad;
    }
    OmniCullResult r = detail::omni_cull(in, [&](std::size_t i, std::uint8_t m) {
        if (i < mask_capacity) face_masks[i] = m;
    });
    if (r.status != Status::Ok) return r;
    r.needed = r.caster_count;
    r.count = std::min(mask_capacity, r.caster_count);
    if (mask_capacity < r.caster_count) {
        r.status = Status::BufferTooSmall;
        r.detail = "mask_capacity: below needed (see needed)";
    }
    return r;
}

/// Per-face index lists: `lists` holds `capacity` uint32 elements; it needs `draws` (`needed`, at
/// most 6 * caster_count); face f draws lists[face_offsets[f] .. face_offsets[f + 1]) (caster
/// indices ascending). `face_offsets` holds 7 size_t elements (required, never null). If
/// capacity < draws: BufferTooSmall, nothing written to lists (`count` 0), face_offsets still
/// filled. lists null with capacity > 0, face_offsets null or more than 2^32 - 1 casters ->
/// InvalidArgument.
inline OmniCullResult omni_cull_face_lists(const OmniCullInput& in, std::uint32_t* lists, std::size_t capacity,
                                           std::size_t face_offsets[7]) {
    if ((!lists && capacity != 0) || !face_offsets) {
        OmniCullResult bad;
        bad.status = Status::InvalidArgument;
        bad.detail = !face_offsets ? "face_offsets: null" : "lists: null with capacity > 0";
        return bad;
    }
    OmniCullResult r = detail::omni_cull(in, [](std::size_t, std::uint8_t) {});
    if (r.status != Status::Ok) return r;
    r.needed = r.draws;
    if (r.caster_count > 0xFFFFFFFFull) {
        r.status = Status::InvalidArgument;
        r.detail = "box_count + sphere_count: beyond uint32 indices";
        return r;
    }
    face_offsets[0] = 0;
    for (int f = 0; f < 6; ++f) face_offsets[f + 1] = face_offsets[f] + r.face_draws[f];
    if (capacity < r.draws) {
        r.status = Status::BufferTooSmall;
        r.detail = "capacity: below needed (see needed)";
        return r;
    }
    r.count = r.draws;
    std::size_t cursor[6];
    for (int f = 0; f < 6; ++f) cursor[f] = face_offsets[f];
    detail::omni_cull(in, [&](std::size_t i, std::uint8_t m) {
        for (int f = 0; f < 6; ++f)
            if (m & (1u << f)) lists[cursor[f]++] = static_cast<std::uint32_t>(i);
    });
    return r;
}

// ------------------------------------------------------------------------------ dual paraboloid

/// Front: local z >= 0 (the paraboloid frame's axis), Back: local z < 0.
enum class OmniHemisphere : std::uint8_t { Front = 0, Back = 1 };

/// Result of omni_paraboloid_frame.
struct OmniParaboloidFrame {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::mat4 view{1.0f};  ///< world -> paraboloid frame: light at the origin, `axis` = +z (right-handed)
};

/// Paraboloid frame: z = normalize(axis), x = normalize(cross(up, z)), y = cross(z, x).
/// (Unlike lookAt, the front map looks down +z.) light_position: a point light (w > 0), else
/// InvalidLight; axis or up NaN/Inf -> NonFinite; axis zero or up parallel to it (or zero) ->
/// InvalidArgument; a translation beyond float -> Overflow.
inline OmniParaboloidFrame omni_paraboloid_frame(const glm::vec4& light_position, const glm::vec3& axis,
                                                 const glm::vec3& up) {
    OmniParaboloidFrame fr;
    glm::dvec3 l;
    fr.status = detail::omni_point_light(light_position, l, fr.detail);
    if (fr.status != Status::Ok) return fr;
    fr.status = Status::NotRun;
    if (!detail::omni_finite3(axis) || !detail::omni_finite3(up)) {
        fr.status = Status::NonFinite;
        fr.detail = !detail::omni_finite3(axis) ? "axis: NaN or Inf" : "up: NaN or Inf";
        return fr;
    }
    const glm::dvec3 a(axis), u(up);
    const double la = glm::length(a);
    if (!(la > 0.0) || !std::isfinite(la)) {
        fr.status = Status::InvalidArgument;
        fr.detail = "axis: zero";
        return fr;
    }
    const glm::dvec3 z = a / la;
    glm::dvec3 x = glm::cross(u, z);
    const double lx = glm::length(x);
    if (!(lx > 1e-6 * glm::length(u)) || !std::isfinite(lx)) {
        fr.status = Status::InvalidArgument;  // up parallel to the axis (or zero)
        fr.detail = "up: parallel to axis (or zero)";
        return fr;
    }
    x /= lx;
    const glm::dvec3 y = glm::cross(z, x);
    glm::dmat4 V(1.0);
    for (int c = 0; c < 3; ++c) {
        V[c][0] = x[c];
        V[c][1] = y[c];
        V[c][2] = z[c];
    }
    V[3][0] = -glm::dot(x, l);
    V[3][1] = -glm::dot(y, l);
    V[3][2] = -glm::dot(z, l);
    fr.view = glm::mat4(V);
    if (!detail::omni_finite_mat(fr.view)) {
        fr.status = Status::Overflow;
        fr.detail = "light_position: view matrix beyond float";
        return fr;
    }
    fr.status = Status::Ok;
    return fr;
}

/// Result of omni_paraboloid_project.
struct OmniParaboloidPoint {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    OmniHemisphere hemisphere = OmniHemisphere::Front;
    glm::vec2 xy{0.0f};  ///< in the unit disk; texture uv = xy * 0.5 + 0.5 of that hemisphere's map
};

/// Paraboloid projection of a direction in the frame (need not be unit length): the point of the
/// paraboloid f(x,y) = 1/2 - (x^2+y^2)/2 that reflects d into the axis (Brabec et al. 2002, sec. 3):
/// front (d.z >= 0, ties at the rim go to Front) xy = d.xy / (1 + d.z), back xy = d.xy / (1 - d.z)
/// for unit d (the stereographic projection from the opposite pole; both maps share x and y).
/// NaN/Inf -> NonFinite, the zero vector -> InvalidArgument.
inline OmniParaboloidPoint omni_paraboloid_project(const glm::vec3& d) {
    OmniParaboloidPoint p;
    if (!detail::omni_finite3(d)) {
        p.status = Status::NonFinite;
        p.detail = "d: NaN or Inf";
        return p;
    }
    const glm::dvec3 v(d);
    const double len = glm::length(v);
    if (!(len > 0.0) || !std::isfinite(len)) {
        p.status = Status::InvalidArgument;
        p.detail = "d: zero vector";
        return p;
    }
    const glm::dvec3 n = v / len;
    const bool front = n.z >= 0.0;
    const double den = 1.0 + (front ? n.z : -n.z);  // in [1, 2]
    p.hemisphere = front ? OmniHemisphere::Front : OmniHemisphere::Back;
    p.xy = glm::vec2(static_cast<float>(n.x / den), static_cast<float>(n.y / den));
    p.status = Status::Ok;
    return p;
}

/// Inverse: the unit direction of map point xy (Brabec et al. 2002): front
/// d = (2x, 2y, 1 - r^2) / (1 + r^2), back the same with z negated. Defined for every finite xy:
/// r > 1 continues across the rim into the other hemisphere (front xy -> back xy / r^2), which is
/// how filters cross the seam. NaN/Inf xy -> NonFinite, a hemisphere outside the enum ->
/// InvalidArgument.
inline OmniDirection omni_paraboloid_unproject(OmniHemisphere h, const glm::vec2& xy) {
    OmniDirection r;
    if (h != OmniHemisphere::Front && h != OmniHemisphere::Back) {
        r.status = Status::InvalidArgument;
        r.detail = "h: unknown OmniHemisphere";
        return r;
    }
    if (!std::isfinite(xy.x) || !std::isfinite(xy.y)) {
        r.status = Status::NonFinite;
        r.detail = "xy: NaN or Inf";
        return r;
    }
    const double x = xy.x, y = xy.y, r2 = x * x + y * y;  // finite: |xy| <= FLT_MAX
    glm::dvec3 d(2.0 * x, 2.0 * y, 1.0 - r2);
    d /= (1.0 + r2);
    if (h == OmniHemisphere::Back) d.z = -d.z;
    d = glm::normalize(d);  // already unit up to rounding; keeps huge r2 well-defined
    r.direction = glm::vec3(d);
    r.status = detail::omni_finite3(r.direction) ? Status::Ok : Status::Overflow;
    r.detail = r.status == Status::Ok ? nullptr : "xy: so large the direction is not finite";
    return r;
}

/// Largest angle subtended by one texel at map radius r of a `size`-texel paraboloid map: the
/// projection is conformal with scale (1 + r^2) / 2 (map units per radian), a texel is 2 / size
/// map units; evaluated at max(r - 2 texels, 0) so that it holds over a filter's footprint.
/// 4 / size at the center, 2 / size at the rim. size 0 -> InvalidArgument, r NaN/Inf -> NonFinite.
inline OmniValue omni_paraboloid_texel_angle(std::uint32_t size, float r) {
    OmniValue v;
    if (size == 0) {
        v.status = Status::InvalidArgument;
        v.detail = "size: 0";
        return v;
    }
    if (!std::isfinite(r)) {
        v.status = Status::NonFinite;
        v.detail = "r: NaN or Inf";
        return v;
    }
    const double texel = 2.0 / size;
    const double rr = std::max(0.0, std::fabs(static_cast<double>(r)) - 2.0 * texel);
    v.value = static_cast<float>(texel * 2.0 / (1.0 + rr * rr));  // rr^2 may be +inf: value 0, finite
    v.status = Status::Ok;
    return v;
}

/// Result of omni_paraboloid_edge_error.
struct OmniEdgeErrorResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float texels = 0.0f;            ///< bound on the deviation between the curved image and the drawn chord
    float subtended_angle = 0.0f;   ///< [Units: rad] bound on the angle the edge subtends at the light
};

namespace detail {
// Largest sagitta of an arc of length l on a circle of radius R >= 1: R (1 - cos(l / 2R)); it
// grows with 1/R while l / 2R <= 2.3311 (the maximum of (1 - cos u) / u), hence:
inline double omni_max_sagitta(double l) {
    const double u_star = 2.3311223704144226, peak = 0.7246113537767085;  // argmax and max of (1 - cos u) / u
    return l * 0.5 <= u_star ? 1.0 - std::cos(0.5 * l) : 0.5 * l * peak;
}
}  // namespace detail

/// Tessellation error of a paraboloid map (Brabec et al. 2002 assume fine tessellation): a straight
/// edge of length L whose points are all at distance >= D from the light maps to a curve, but the
/// rasterizer draws the chord between its end points. Derivation:
///  1. the edge subtends at most phi = 2 atan(L / 2D) at the light (the centered case; an edge whose
///     nearest point is an end point subtends less);
///  2. the map is the stereographic projection from the opposite pole, which maps the edge's great
///     circle (plane normal m) to a circle of radius 1 / |m.z| >= 1 (map units), conformally with
///     scale (1 + r^2) / 2, so within radius R the image arc is at most l = phi (1 + R^2) / 2 long;
///  3. an arc of length l on a circle of radius >= 1 deviates from its chord by at most
///     1 - cos(l / 2) (l <= 4.66; beyond, 0.7246 l / 2), and a map unit is size / 2 texels.
/// Bound = size / 2 * (1 - cos(l / 2)). It is attained (factor 1) by an edge centered on its
/// foot point, perpendicular to the axis, on the rim (R = 1: the equator maps to the unit circle
/// isometrically). `max_radius` R [Limit: (0, 1e4]]: the part of the map the edge's image stays
/// within (1 = its hemisphere; a clip margin beyond the rim needs R > 1; R < 1 is valid but not
/// tight); the bound never exceeds the diameter 2R of that disk. distance may be +inf (bound 0).
/// Statuses: size 0 or above 65536, edge_length or distance < 0, max_radius outside (0, 1e4] ->
/// InvalidArgument; NaN (and an infinite edge_length or max_radius) -> NonFinite.
inline OmniEdgeErrorResult omni_paraboloid_edge_error(float edge_length, float distance, std::uint32_t size,
                                                      float max_radius = 1.0f) {
    OmniEdgeErrorResult r;
    if (!std::isfinite(edge_length) || std::isnan(distance) || !std::isfinite(max_radius)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(edge_length) ? "edge_length: NaN or Inf" : (std::isnan(distance) ? "distance: NaN" : "max_radius: NaN or Inf");
        return r;
    }
    if (size == 0 || size > 65536 || edge_length < 0.0f || distance < 0.0f || !(max_radius > 0.0f) || max_radius > 1e4f) {
        r.status = Status::InvalidArgument;
        r.detail = size == 0 || size > 65536 ? "size: outside [1, 65536]"
                   : (edge_length < 0.0f ? "edge_length: < 0" : (distance < 0.0f ? "distance: < 0" : "max_radius: outside (0, 1e4]"));
        return r;
    }
    const double L = edge_length, D = distance;
    const double phi = D == 0.0 ? (L > 0.0 ? 3.141592653589793 : 0.0) : 2.0 * std::atan(L / (2.0 * D));
    const double R = max_radius;
    const double l = phi * 0.5 * (1.0 + R * R);
    r.subtended_angle = static_cast<float>(phi);
    // the image stays in the disk of radius R: never more than its diameter
    r.texels = static_cast<float>(0.5 * size * std::min(detail::omni_max_sagitta(l), 2.0 * R));
    r.status = Status::Ok;
    return r;
}

/// Result of omni_paraboloid_max_edge_length.
struct OmniEdgeLengthResult {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    float length = 0.0f;     ///< [Units: wu] longest edge at that distance whose image deviates <= max_texels
    bool unlimited = false;  ///< true (with Ok): any edge passes (max_texels that large); length = FLT_MAX
};

/// Inverse of omni_paraboloid_edge_error (R = max_radius): the longest edge at distance >= D whose
/// paraboloid image stays within max_texels of the drawn chord: l = 2 acos(1 - 2 e / size),
/// phi = 2 l / (1 + R^2), L = 2 D tan(phi / 2)
/// (l = 2 e / (0.7246 size) past the sagitta's turning point). Tessellate casters so that every edge is shorter.
/// When max_texels is so large that any edge passes: `unlimited` = true, length = FLT_MAX (Ok).
/// Statuses: size 0 or above 65536, distance or max_texels < 0, max_radius outside (0, 1e4] ->
/// InvalidArgument; NaN or an infinite distance or max_radius -> NonFinite (max_texels may be +inf);
/// a length beyond float (distance near FLT_MAX) -> Overflow.
inline OmniEdgeLengthResult omni_paraboloid_max_edge_length(float distance, std::uint32_t size, float max_texels,
                                                            float max_radius = 1.0f) {
    OmniEdgeLengthResult r;
    if (!std::isfinite(distance) || std::isnan(max_texels) || !std::isfinite(max_radius)) {
        r.status = Status::NonFinite;
        r.detail = !std::isfinite(distance) ? "distance: NaN or Inf" : (std::isnan(max_texels) ? "max_texels: NaN" : "max_radius: NaN or Inf");
        return r;
    }
    if (size == 0 || size > 65536 || distance < 0.0f || max_texels < 0.0f || !(max_radius > 0.0f) || max_radius > 1e4f) {
        r.status = Status::InvalidArgument;
        r.detail = size == 0 || size > 65536 ? "size: outside [1, 65536]"
                   : (distance < 0.0f ? "distance: < 0" : (max_texels < 0.0f ? "max_texels: < 0" : "max_radius: outside (0, 1e4]"));
        return r;
    }
    const double sag = 2.0 * static_cast<double>(max_texels) / size;  // allowed deviation, map units
    const double u_star = 2.3311223704144226, peak = 0.7246113537767085;
    const double l = sag <= 1.0 - std::cos(u_star) ? 2.0 * std::acos(1.0 - sag) : 2.0 * sag / peak;
    const double k = 0.5 * (1.0 + static_cast<double>(max_radius) * max_radius);
    const double phi = l / k;
    if (phi >= 3.141592653589793) {
        r.length = std::numeric_limits<float>::max();
        r.unlimited = true;
    } else {
        r.length = static_cast<float>(2.0 * static_cast<double>(distance) * std::tan(0.5 * phi));
        if (!std::isfinite(r.length)) {
            r.length = 0.0f;
            r.status = Status::Overflow;
            r.detail = "length: beyond float range";
            return r;
        }
    }
    r.status = Status::Ok;
    return r;
}

}  // namespace shadowkit

// shadowkit/virtual_shadow_map.hpp - virtual shadow maps (CPU side; glsl/virtual_shadow_map.glsl marks and looks up): clipmap layout, page table, physical page pool with LRU eviction, invalidation by moving casters and scrolling, the pages to render each frame.
//
// Usage (once: allocates; then per frame: no allocation):
//   shadowkit::VsmLayout layout;
//   layout.level0_extent_world = 32.0;           // side of the finest clipmap level, world units (required)
//   layout.level_count = 12; layout.pool_pages = 4096;
//   shadowkit::VsmState vsm;
//   if (shadowkit::vsm_state_init(layout, vsm).status != shadowkit::Status::Ok) { /* bad layout */ }
//   // each frame: 1. mark (GPU: every visible pixel writes the page it will sample, read back as
//   // VsmPageRequest), 2. plan, 3. render the listed pages into the physical pool, 4. look up.
//   shadowkit::VsmFrame f;
//   f.camera_position = camera_world;  f.light_position = sun;   // double camera, w = 0 light
//   f.requests = requests; f.request_count = n;
//   f.moved_casters = moves; f.moved_caster_count = m;           // old and new bounds of moved casters
//   std::vector<shadowkit::VsmPageRender> pages(layout.pool_pages);   // once
//   const shadowkit::VsmPlan plan = shadowkit::vsm_plan(vsm, f, pages.data(), pages.size());
//   for (std::size_t i = 0; i < plan.count; ++i) { /* viewport = pages[i].atlas_x/y, draw with pages[i].view_proj */ }
//   shadowkit::vsm_gpu_block(vsm, camera_world, words, n);  // the SSBO glsl/virtual_shadow_map.glsl reads:
//   upload(words);  // level matrices relative to the camera + the page table (vsm_table_index), for the lookup
//
// Conventions:
// Lights: a light is its homogeneous position `light_position` = (x, y, z, w), as OpenGL's
// GL_POSITION and Everitt & Kilgard use it. w > 0: a point or spot light at xyz / w. w = 0: a
// directional light at infinity in direction xyz, the direction *toward* the light (its rays travel
// along -xyz). w < 0, (0, 0, 0, 0) and NaN/Inf are rejected with Status::InvalidLight.
//   A directional light gets `level_count` clipmap levels; a spot light (w > 0, with spot_direction
//   and spot_cone_half_angle_radians) gets one virtual map (level_count must be 1).
//   Units: world units for extents and positions (camera in double), texels for page and virtual
//   sizes, pages for the pool. Pages: (level, page x, page y), x and y in [0, pages per side) on the
//   level's current window (x right, y up in the light's view). Matrices: glm::dmat4 world -> clip,
//   column-major, `ClipDepth` + `reversed_z`; build a float matrix relative to a point near the
//   camera with vsm_relative_matrix (a float world -> clip at 1e6 units loses whole texels).
//   Boxes: 6 floats, min x, y, z then max x, y, z, world units; min > max on any axis: empty.
//   Buffers: counted in elements of the pointer's type. Per-frame functions never allocate.
//
// Based on:
//   C. Tanner, C. Migdal, M. Jones 1998, "The Clipmap: A Virtual Mipmap" (SIGGRAPH): nested levels
//     of twice the extent, centered on the viewer, addressed toroidally so a move loads only the border.
//   A. Lefohn, S. Sengupta, J. Owens 2007, "Resolution-Matched Shadow Maps" (ACM TOG 26(4)): pages
//     requested by the visible pixels, a page table, a physical page pool kept across frames.
//   Epic Games 2021, "Virtual Shadow Maps" (Unreal Engine 5 documentation): 16k virtual maps per
//     clipmap level, 128-texel pages, cached pages invalidated by moving casters' bounds.
//
// MIT License. Copyright (c) shadowkit contributors.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

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

/// Most clipmap levels.
constexpr int kVsmMaxLevels = 16;
/// Most page-table entries (level_count * pages per side^2).
constexpr std::size_t kVsmMaxTableEntries = std::size_t(1) << 22;
/// Most physical pages in the pool.
constexpr int kVsmMaxPoolPages = 1 << 20;
/// Page-table entry bit: the page is resident and its content is current: sample slot (entry & kVsmSlotMask).
constexpr std::uint32_t kVsmPageValid = 0x80000000u;
/// Page-table entry bit: the page owns a physical slot whose content is stale (a moved caster; not
/// requested since). The lookup treats it as missing, like an entry without kVsmPageValid.
constexpr std::uint32_t kVsmPageAllocated = 0x40000000u;
/// Page-table entry bits holding the physical slot.
constexpr std::uint32_t kVsmSlotMask = 0x3FFFFFFFu;
/// "No slot" / "no page" marker in the state's links.
constexpr std::uint32_t kVsmNone = 0xFFFFFFFFu;

/// The virtual layout and the pool (vsm_state_init). Fixed for a state's life.
struct VsmLayout {
    int page_texels = 128;             ///< side of a page in texels [Limit: 8 .. 4096]
    int virtual_texels = 16384;        ///< side of a level's virtual map, texels: a multiple of page_texels, 2 .. 4096 pages per side
    int level_count = 16;              ///< clipmap levels (directional light) [Limit: 1 .. kVsmMaxLevels]; a spot light uses 1
    int pool_pages = 4096;             ///< physical pages in the pool [Limit: 1 .. kVsmMaxPoolPages]
    int pool_columns = 0;              ///< pages per row of the physical atlas; 0: ceil(sqrt(pool_pages))
    double level0_extent_world = 0.0;  ///< side of level 0 (the finest) in world units; level k covers 2^k times it (required, directional) [Limit: 1e-30 .. 1e30]
    double depth_range_world = 1000.0; ///< directional: the pages' depth covers camera depth +- 3/4 of this along the light (see VsmPageRender::view_proj) [Limit: 1e-30 .. 1e30]
    double spot_near_world = 0.1;      ///< spot: near plane distance
    double spot_far_world = 1000.0;    ///< spot: far plane distance (> near)
    ClipDepth clip_depth = ClipDepth::NegativeOneToOne;
    bool reversed_z = false;
};

/// One requested page, as the GPU marking pass writes it: the level and the page on the level's
/// current window (the window of the frame the marking ran with: mark with last frame's lookup data
/// and plan before this frame's camera moves, or mark and plan with the same camera).
struct VsmPageRequest {
    std::uint32_t level = 0;   ///< [0, level_count)
    std::uint32_t x = 0, y = 0;///< [0, pages per side)
};

/// A caster that moved since the last plan: its world bounds then and now (6 floats each). The pages
/// either box overlaps (over every level, the full depth along the light) are re-rendered.
struct VsmCasterMove {
    float previous_bounds[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};  ///< last frame (min > max: it appeared)
    float bounds[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};           ///< this frame (min > max: it was removed)
};

/// What vsm_plan needs this frame.
struct VsmFrame {
    glm::dvec3 camera_position = glm::dvec3(0.0);   ///< world, double: the clipmap levels center on it
    glm::vec4 light_position = glm::vec4(0.0f);     ///< (required) w = 0 directional, w > 0 spot
    glm::vec3 spot_direction = glm::vec3(0.0f);     ///< spot: the axis the light shines along (required for a spot)
    float spot_cone_half_angle_radians = 0.0f;      ///< spot: (0, 1.5] (required for a spot)
    const VsmPageRequest* requests = nullptr;       ///< request_count requests (duplicates allowed)
    std::size_t request_count = 0;
    const VsmCasterMove* moved_casters = nullptr;   ///< moved_caster_count moves (only casters that moved)
    std::size_t moved_caster_count = 0;
};

/// One page to render this frame: draw the casters with `view_proj` into the viewport
/// (atlas_x, atlas_y, page_texels, page_texels) of the physical pool, after clearing it.
struct VsmPageRender {
    std::uint32_t level = 0;
    std::uint32_t x = 0, y = 0;      ///< the page on the level's window, as requested
    std::uint32_t slot = 0;          ///< physical slot [0, pool_pages)
    int atlas_x = 0, atlas_y = 0;    ///< texel origin of the slot in the pool atlas
    /// world -> clip of the page alone (double): x, y in [-1, 1] exactly over the page. Directional:
    /// orthographic, depth over [c - D, c + D] along the light, D = depth_range_world, c the camera's
    /// depth snapped to D / 2 (c moves by whole steps; all pages re-render when it does). Use depth clamp.
    glm::dmat4 view_proj = glm::dmat4(1.0);
};

/// Per level, what the lookup needs (VsmState::levels).
struct VsmLevelLookup {
    /// world -> (u, v, depth, w): (u, v) / w in [0, 1) over the level's window, page = floor(u / w *
    /// pages per side); depth / w as the pages store it (for a spot light, divide by w).
    glm::dmat4 world_to_uv = glm::dmat4(1.0);
    /// Toroidal offset: page (x, y) of the window has page-table column (x + origin_mod_x) mod
    /// pages per side and row (y + origin_mod_y) mod pages per side.
    int origin_mod_x = 0, origin_mod_y = 0;
    double page_world = 0.0;         ///< directional: a page's side in world units
};

/// The plan of one frame (vsm_plan).
struct VsmPlan {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;           ///< pages written to `pages`, to render this frame
    /// Pool pages needed to map every distinct requested page at its own level. With
    /// BufferTooSmall (needed > pool_pages) the plan is still applied and usable: see `fallback`.
    std::size_t needed = 0;
    std::size_t requested = 0;       ///< distinct requested pages (== needed)
    std::size_t kept = 0;            ///< requested pages resident and current: not rendered
    std::size_t allocated = 0;       ///< pages given a slot this frame (rendered)
    std::size_t rerendered = 0;      ///< requested pages resident but stale (moved casters): rendered in place
    std::size_t evicted = 0;         ///< least-recently-requested pages evicted for them
    std::size_t invalidated = 0;     ///< resident pages a moved caster's old or new bounds overlap (made stale)
    std::size_t scrolled_out = 0;    ///< resident pages freed because their level's window moved past them
    /// Pool too small (BufferTooSmall): requested pages not mapped at their own level: replaced by
    /// their parents on the next coarser level (the lookup falls back to it), finest level first,
    /// page by page, until the requests fit.
    std::size_t fallback = 0;
    /// Requested pages whose page and every coarser page is missing: only when even the coarsest
    /// level's requests exceed the pool. 0 when the pool holds them: never a hole.
    std::size_t unmapped = 0;
    /// Finest level whose requests were mapped, in whole or in part: requests of finer levels fell back
    /// to it or to the next coarser level (level_count when nothing was requested).
    int finest_level = 0;
    bool everything_invalidated = false; ///< the light changed or the depth center stepped: all resident pages were stale
};

/// Caster indices per rendered page (vsm_page_casters).
struct VsmPageCasters {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;           ///< indices written (a valid prefix when Ok)
    std::size_t needed = 0;          ///< indices the lists need: count when Ok
};

/// One slot of the physical pool (state internals, public for tests and debug views).
struct VsmSlot {
    std::int64_t x = 0, y = 0;       ///< the page's absolute coordinates on its level's page grid
    std::uint32_t level = 0;
    std::uint32_t prev = kVsmNone, next = kVsmNone;  ///< LRU list: head = most recently requested
    std::uint32_t last_request = 0;  ///< frame number of the last request
    std::uint32_t render_frame = 0;  ///< frame it was last listed to render
    std::uint32_t render_index = 0;  ///< its index in that frame's page list
    bool resident = false;
};

/// Page table, pool and clipmap windows, kept across frames (vsm_state_init allocates; vsm_plan
/// updates it without allocating).
struct VsmState {
    VsmLayout layout;
    int pages_per_side = 0;
    bool initialized = false;
    bool has_light = false;                   ///< a plan has placed the levels
    glm::vec4 light_position = glm::vec4(0.0f);
    glm::vec3 spot_direction = glm::vec3(0.0f);
    float spot_cone_half_angle_radians = 0.0f;
    glm::dvec3 axis_x = glm::dvec3(1, 0, 0), axis_y = glm::dvec3(0, 1, 0), axis_z = glm::dvec3(0, 0, 1);
    glm::dmat4 spot_view_proj = glm::dmat4(1.0);
    double depth_center = 0.0;
    std::int64_t origin_x[kVsmMaxLevels] = {}, origin_y[kVsmMaxLevels] = {};  ///< absolute page of each window's (0, 0)
    VsmLevelLookup levels[kVsmMaxLevels];
    std::uint32_t frame = 0;
    /// The page table the lookup reads: level_count * pages_per_side^2 uints at vsm_table_index:
    /// kVsmPageValid | slot (resident and current), kVsmPageAllocated | slot (stale), or 0 (missing).
    std::vector<std::uint32_t> page_table;
    std::vector<std::uint32_t> request_stamp; ///< frame of the last request, per table entry
    std::vector<VsmSlot> slots;
    std::vector<std::uint32_t> free_slots;
    std::size_t free_count = 0;
    std::uint32_t lru_head = kVsmNone, lru_tail = kVsmNone;
    std::vector<std::uint32_t> work;          ///< distinct requests this frame (packed)
    std::vector<std::uint32_t> work_next;     ///< next work item of the same level (per-level lists)
    std::uint32_t level_head[kVsmMaxLevels] = {}, level_tail[kVsmMaxLevels] = {};
    std::size_t work_count = 0;
};

/// A float matrix (vsm_relative_matrix).
struct VsmMatrix {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    glm::mat4 matrix = glm::mat4(1.0f);
};

/// The result of vsm_state_init.
struct VsmInit {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t bytes = 0;           ///< CPU memory the state holds
    std::size_t table_entries = 0;   ///< uints in page_table (the GPU buffer's size)
};

namespace detail {

inline std::int64_t vsm_floor_div(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}
inline std::int64_t vsm_floor_mod(std::int64_t a, std::int64_t b) { return a - vsm_floor_div(a, b) * b; }

inline bool vsm_box_finite(const float* b) {
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(b[i])) return false;
    return true;
}
inline bool vsm_box_empty(const float* b) { return b[0] > b[3] || b[1] > b[4] || b[2] > b[5]; }

inline std::uint32_t vsm_pack(std::uint32_t level, std::uint32_t x, std::uint32_t y) { return (level << 24) | (y << 12) | x; }
inline std::uint32_t vsm_unpack_level(std::uint32_t p) { return (p >> 24) & 0x1Fu; }
inline std::uint32_t vsm_unpack_x(std::uint32_t p) { return p & 0xFFFu; }
inline std::uint32_t vsm_unpack_y(std::uint32_t p) { return (p >> 12) & 0xFFFu; }
constexpr std::uint32_t kVsmTombstone = 0xFFFFFFFFu;

inline double vsm_page_world(const VsmState& s, int level) {
    return s.layout.level0_extent_world * std::ldexp(1.0, level) / double(s.pages_per_side);
}

inline bool vsm_directional(const VsmState& s) { return s.light_position.w == 0.0f; }

/// Table entry of the absolute page (ax, ay) of `level` (toroidal).
inline std::size_t vsm_entry_abs(const VsmState& s, int level, std::int64_t ax, std::int64_t ay) {
    const std::int64_t n = s.pages_per_side;
    return std::size_t(level) * std::size_t(n * n) + std::size_t(vsm_floor_mod(ay, n) * n + vsm_floor_mod(ax, n));
}

inline void vsm_lru_unlink(VsmState& s, std::uint32_t i) {
    VsmSlot& e = s.slots[i];
    if (e.prev != kVsmNone) s.slots[e.prev].next = e.next; else s.lru_head = e.next;
    if (e.next != kVsmNone) s.slots[e.next].prev = e.prev; else s.lru_tail = e.prev;
    e.prev = e.next = kVsmNone;
}
inline void vsm_lru_push_front(VsmState& s, std::uint32_t i) {
    VsmSlot& e = s.slots[i];
    e.prev = kVsmNone;
    e.next = s.lru_head;
    if (s.lru_head != kVsmNone) s.slots[s.lru_head].prev = i;
    s.lru_head = i;
    if (s.lru_tail == kVsmNone) s.lru_tail = i;
}

/// Frees slot i: its page-table entry goes to 0, the slot to the free list.
inline void vsm_free_slot(VsmState& s, std::uint32_t i) {
    VsmSlot& e = s.slots[i];
    if (!e.resident) return;
    s.page_table[vsm_entry_abs(s, int(e.level), e.x, e.y)] = 0u;
    vsm_lru_unlink(s, i);
    e.resident = false;
    s.free_slots[s.free_count++] = i;
}

/// Marks every resident page stale (its content no longer matches). O(resident pages).
inline std::size_t vsm_stale_all(VsmState& s) {
    std::size_t n = 0;
    for (std::uint32_t i = s.lru_head; i != kVsmNone; i = s.slots[i].next) {
        std::uint32_t& t = s.page_table[vsm_entry_abs(s, int(s.slots[i].level), s.slots[i].x, s.slots[i].y)];
        if (t & kVsmPageValid) ++n;
        t = kVsmPageAllocated | i;
    }
    return n;
}

/// Frees every resident page. O(resident pages).
inline void vsm_free_all(VsmState& s) {
    while (s.lru_head != kVsmNone) vsm_free_slot(s, s.lru_head);
}

/// Light basis in double: axis_z toward the light, axis_x / axis_y span the map (right-handed).
inline void vsm_light_basis(const glm::dvec3& toward, glm::dvec3& ax, glm::dvec3& ay, glm::dvec3& az) {
    az = glm::normalize(toward);
    const glm::dvec3 up = std::fabs(az.y) < 0.99 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    ax = glm::normalize(glm::cross(up, az));
    ay = glm::cross(az, ax);
}

/// Depth row (clip z as a function of light-space depth w along axis_z) for the directional pages.
inline void vsm_depth_row(const VsmState& s, double& kz, double& cz) {
    const double d = s.layout.depth_range_world;
    // t = (c + d - w) / (2 d): 0 nearest the light, 1 farthest
    double a = -1.0 / (2.0 * d), b = (s.depth_center + d) / (2.0 * d);
    if (s.layout.reversed_z) { a = -a; b = 1.0 - b; }
    if (s.layout.clip_depth == ClipDepth::NegativeOneToOne) { a *= 2.0; b = 2.0 * b - 1.0; }
    kz = a;
    cz = b;
}

/// A directional map matrix: clip x = 2 (u / (n_x P) - x0) - 1 over the rectangle of n pages from
/// absolute page (x0, y0), P the page side in world units.
inline glm::dmat4 vsm_ortho(const VsmState& s, double page, std::int64_t x0, std::int64_t y0, double n_pages) {
    double kz = 0.0, cz = 0.0;
    vsm_depth_row(s, kz, cz);
    const double k = 2.0 / (page * n_pages);
    glm::dmat4 m(0.0);
    for (int c = 0; c < 3; ++c) {
        m[c][0] = k * s.axis_x[c];
        m[c][1] = k * s.axis_y[c];
        m[c][2] = kz * s.axis_z[c];
    }
    m[3][0] = -2.0 * double(x0) / n_pages - 1.0;
    m[3][1] = -2.0 * double(y0) / n_pages - 1.0;
    m[3][2] = cz;
    m[3][3] = 1.0;
    return m;
}

/// World -> clip of the page (level, absolute x, y).
inline glm::dmat4 vsm_page_matrix(const VsmState& s, int level, std::int64_t ax, std::int64_t ay) {
    if (vsm_directional(s)) return vsm_ortho(s, vsm_page_world(s, level), ax, ay, 1.0);
    // spot: crop the NDC square [x0, x1] x [y0, y1] of the page to [-1, 1] (applied to clip: x' = sx x + tx w)
    const double n = double(s.pages_per_side);
    const double x0 = -1.0 + 2.0 * double(ax) / n, y0 = -1.0 + 2.0 * double(ay) / n;
    glm::dmat4 crop(1.0);
    crop[0][0] = n;
    crop[1][1] = n;
    crop[3][0] = -n * (x0 + 1.0 / n);
    crop[3][1] = -n * (y0 + 1.0 / n);
    return crop * s.spot_view_proj;
}

/// Page rectangle (absolute pages, inclusive) a non-empty finite box can shadow on `level`, clipped
/// to the level's window. False: nothing on the window.
inline bool vsm_box_pages(const VsmState& s, int level, const float* b, std::int64_t r[4]) {
    const std::int64_t n = s.pages_per_side;
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    bool behind = false;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 p(b[(c & 1) ? 3 : 0], b[(c & 2) ? 4 : 1], b[(c & 4) ? 5 : 2]);
        double q[2];
        if (vsm_directional(s)) {
            const double page = vsm_page_world(s, level);
            q[0] = glm::dot(p, s.axis_x) / page;
            q[1] = glm::dot(p, s.axis_y) / page;
        } else {
            const glm::dvec4 h = s.spot_view_proj * glm::dvec4(p, 1.0);
            if (!(h.w > 1e-12)) { behind = true; break; }
            q[0] = (h.x / h.w + 1.0) * 0.5 * double(n);
            q[1] = (h.y / h.w + 1.0) * 0.5 * double(n);
        }
        for (int k = 0; k < 2; ++k) { lo[k] = std::fmin(lo[k], q[k]); hi[k] = std::fmax(hi[k], q[k]); }
    }
    const std::int64_t ox = s.origin_x[level], oy = s.origin_y[level];
    if (behind) { r[0] = ox; r[1] = oy; r[2] = ox + n - 1; r[3] = oy + n - 1; return true; }
    const double wlo[2] = {double(ox), double(oy)}, whi[2] = {double(ox + n), double(oy + n)};
    for (int k = 0; k < 2; ++k) {
        if (!(hi[k] >= wlo[k] && lo[k] <= whi[k])) return false;  // also rejects NaN
        r[k] = std::int64_t(std::floor(std::fmax(lo[k], wlo[k])));
        r[k + 2] = std::int64_t(std::floor(std::fmin(hi[k], whi[k])));
        if (r[k] < (k ? oy : ox)) r[k] = k ? oy : ox;
        if (r[k + 2] > (k ? oy : ox) + n - 1) r[k + 2] = (k ? oy : ox) + n - 1;
    }
    return true;
}

/// Makes stale every resident page of every level that the box overlaps. Cost: the smaller of the
/// pages in its rectangle and the resident pages, per level.
inline std::size_t vsm_invalidate_box(VsmState& s, const float* b, std::size_t resident) {
    std::size_t n = 0;
    for (int l = 0; l < s.layout.level_count; ++l) {
        std::int64_t r[4];
        if (!vsm_box_pages(s, l, b, r)) continue;
        const std::uint64_t area = std::uint64_t(r[2] - r[0] + 1) * std::uint64_t(r[3] - r[1] + 1);
        if (area <= resident) {
            for (std::int64_t y = r[1]; y <= r[3]; ++y)
                for (std::int64_t x = r[0]; x <= r[2]; ++x) {
                    std::uint32_t& t = s.page_table[vsm_entry_abs(s, l, x, y)];
                    if (t & kVsmPageValid) { t = kVsmPageAllocated | (t & kVsmSlotMask); ++n; }
                }
        } else {
            for (std::uint32_t i = s.lru_head; i != kVsmNone; i = s.slots[i].next) {
                const VsmSlot& e = s.slots[i];
                if (int(e.level) != l || e.x < r[0] || e.x > r[2] || e.y < r[1] || e.y > r[3]) continue;
                std::uint32_t& t = s.page_table[vsm_entry_abs(s, l, e.x, e.y)];
                if (t & kVsmPageValid) { t = kVsmPageAllocated | i; ++n; }
            }
        }
    }
    return n;
}

/// Frees the resident pages of `level` that left its window when the origin moved from (ox, oy) to
/// (nx, ny). Cost: the pages that left (a border strip; the whole window after a jump).
inline std::size_t vsm_scroll_level(VsmState& s, int level, std::int64_t ox, std::int64_t oy, std::int64_t nx, std::int64_t ny) {
    const std::int64_t n = s.pages_per_side;
    std::size_t freed = 0;
    auto drop = [&](std::int64_t x, std::int64_t y) {
        const std::uint32_t t = s.page_table[vsm_entry_abs(s, level, x, y)];
        if (t == 0u) return;
        const std::uint32_t i = t & kVsmSlotMask;
        if (s.slots[i].x == x && s.slots[i].y == y && int(s.slots[i].level) == level) { vsm_free_slot(s, i); ++freed; }
    };
    const bool jump = nx - ox >= n || ox - nx >= n || ny - oy >= n || oy - ny >= n;
    for (std::int64_t x = ox; x < ox + n; ++x) {
        const bool x_out = jump || x < nx || x >= nx + n;
        if (x_out) {
            for (std::int64_t y = oy; y < oy + n; ++y) drop(x, y);
            continue;
        }
        // the rows of the old window outside the new one: one interval
        const std::int64_t a = ny > oy ? oy : (ny + n > oy ? ny + n : oy);
        const std::int64_t e = ny > oy ? (ny < oy + n ? ny : oy + n) : oy + n;
        if (ny == oy) continue;
        for (std::int64_t y = a; y < e; ++y) drop(x, y);
    }
    return freed;
}

/// Why `s` cannot serve the last plan's pages (the detail of InvalidArgument): not initialized, or no
/// plan has placed its levels; nullptr when it can.
inline const char* vsm_unplaced(const VsmState& s) {
    return !s.initialized ? "s: not initialized (vsm_state_init)"
           : !s.has_light ? "s: no plan has placed its levels yet (vsm_plan)"
                          : nullptr;
}

}  // namespace detail

/// Page-table index of page (x, y) of `level` on the level's current window: the entry the lookup
/// reads is page_table[vsm_table_index(...)]. total: for x, y in [0, pages_per_side) and level in
/// [0, level_count) of an initialized state, an index < page_table.size(); 0 otherwise.
inline std::size_t vsm_table_index(const VsmState& s, std::uint32_t level, std::uint32_t x, std::uint32_t y) {
    if (!s.initialized || level >= std::uint32_t(s.layout.level_count) || x >= std::uint32_t(s.pages_per_side) ||
        y >= std::uint32_t(s.pages_per_side))
        return 0;
    const int l = int(level);
    return detail::vsm_entry_abs(s, l, s.origin_x[l] + std::int64_t(x), s.origin_y[l] + std::int64_t(y));
}

/// Result of vsm_requests_from_bitmask.
struct VsmRequestList {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;           ///< requests written (a valid prefix)
    std::size_t needed = 0;          ///< set bits: requests the whole mask needs (count when Ok)
};

/// uint32 words of a request bitmask: level_count * pages_per_side^2 bits, ceil(bits / 32). total:
/// 0 for an uninitialized state.
inline std::size_t vsm_bitmask_words(const VsmState& s) {
    if (!s.initialized) return 0;
    return (std::size_t(s.layout.level_count) * std::size_t(s.pages_per_side) * std::size_t(s.pages_per_side) + 31) / 32;
}

/// Turns a request bitmask (what a marking pass writes with atomicOr: bit (level * n + y) * n + x of
/// the window, word = bit / 32, bit within the word = bit % 32, n = pages_per_side) into a request
/// list for vsm_plan. `mask` holds `word_count` uint32 (vsm_bitmask_words); `out` holds
/// `out_capacity` VsmPageRequest elements; it needs one per set bit (`needed`; BufferTooSmall writes
/// the first out_capacity). Bits past the last page are ignored. Cost O(words + set bits).
inline VsmRequestList vsm_requests_from_bitmask(const VsmState& s, const std::uint32_t* mask, std::size_t word_count,
                                                VsmPageRequest* out, std::size_t out_capacity) {
    VsmRequestList r;
    const char* why = !s.initialized                     ? "s: not initialized (vsm_state_init)"
                      : mask == nullptr                  ? "mask: null"
                      : word_count != vsm_bitmask_words(s) ? "word_count: not vsm_bitmask_words(s)"
                      : (out == nullptr && out_capacity != 0) ? "out: null with out_capacity > 0"
                                                              : nullptr;
    if (why) {
        r.status = Status::InvalidArgument;
        r.detail = why;
        return r;
    }
    const std::size_t n = std::size_t(s.pages_per_side), bits = std::size_t(s.layout.level_count) * n * n;
    for (std::size_t w = 0; w < word_count; ++w) {
        std::uint32_t m = mask[w];
        while (m != 0u) {
            std::size_t b = 0;
            while (((m >> b) & 1u) == 0u) ++b;
            m &= m - 1u;
            const std::size_t bit = w * 32 + b;
            if (bit >= bits) break;
            if (r.count < out_capacity)
                out[r.count++] = VsmPageRequest{std::uint32_t(bit / (n * n)), std::uint32_t(bit % n), std::uint32_t((bit / n) % n)};
            ++r.needed;
        }
    }
    r.status = r.count == r.needed ? Status::Ok : Status::BufferTooSmall;
    if (r.status != Status::Ok) r.detail = "out_capacity: fewer than the set bits";
    return r;
}

/// A float matrix for vertices given relative to `anchor` (world position minus anchor): m *
/// translate(anchor), computed in double, then rounded to float. Keeps whole-texel accuracy far from
/// the origin when anchor is near the camera. NonFinite for a non-finite input, Overflow when an
/// entry exceeds float.
inline VsmMatrix vsm_relative_matrix(const glm::dmat4& m, const glm::dvec3& anchor) {
    VsmMatrix r;
    glm::dmat4 t = m;
    t[3] = m[0] * anchor.x + m[1] * anchor.y + m[2] * anchor.z + m[3];
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) {
            if (!std::isfinite(m[c][k]) || !std::isfinite(anchor[c % 3])) {
                r.status = Status::NonFinite;
                r.detail = "m, anchor: NaN or Inf";
                return r;
            }
            if (!(std::fabs(t[c][k]) <= 3.0e38)) {
                r.status = Status::Overflow;
                r.detail = "m, anchor: an entry of m * translate(anchor) beyond float";
                return r;
            }
        }
    r.matrix = glm::mat4(t);
    r.status = Status::Ok;
    return r;
}

/// uint32 words before the page table in the GPU block (vsm_gpu_block): 16 mat4, 16 ivec4, 2 ivec4, 1 vec4.
constexpr std::size_t kVsmGpuHeaderWords = 16 * 16 + 16 * 4 + 4 + 4 + 4;

/// Result of vsm_gpu_block.
struct VsmGpuBlock {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    std::size_t count = 0;           ///< uint32 words written (needed when Ok)
    std::size_t needed = 0;          ///< words the block needs: kVsmGpuHeaderWords + page-table entries
};

/// uint32 words of the GPU block (vsm_gpu_block). total: 0 for an uninitialized state.
inline std::size_t vsm_gpu_block_words(const VsmState& s) {
    return s.initialized ? kVsmGpuHeaderWords + s.page_table.size() : 0;
}

/// Writes the std430 buffer glsl/virtual_shadow_map.glsl reads (block SkVsmData), word for word:
/// mat4 sk_vsm_world_to_uv[16] (levels[l].world_to_uv relative to `anchor`, float, column-major;
/// zero past level_count), ivec4 sk_vsm_level[16] (origin_mod_x, origin_mod_y, 0, 0), ivec4
/// sk_vsm_layout (level_count, pages_per_side, page_texels, pool_columns), ivec4 sk_vsm_flags
/// (zero_to_one, reversed_z, directional, 0), vec4 sk_vsm_scale (level 0's texel in world units, 0,
/// 0, 0), then the page table. The shader feeds positions relative to the same anchor (a point near
/// the camera). `out` holds `capacity` uint32 elements; it needs vsm_gpu_block_words (`needed`).
/// InvalidArgument before the first plan (no levels placed); NonFinite / Overflow as vsm_relative_matrix.
inline VsmGpuBlock vsm_gpu_block(const VsmState& s, const glm::dvec3& anchor, std::uint32_t* out, std::size_t capacity) {
    VsmGpuBlock r;
    const char* why = detail::vsm_unplaced(s);
    if (!why && out == nullptr && capacity != 0) why = "out: null with capacity > 0";
    if (why) {
        r.status = Status::InvalidArgument;
        r.detail = why;
        return r;
    }
    r.needed = vsm_gpu_block_words(s);
    if (capacity < r.needed) {
        r.status = Status::BufferTooSmall;
        r.detail = "capacity: below vsm_gpu_block_words(s)";
        return r;
    }
    auto put_float = [&](std::size_t i, float v) {
        std::uint32_t u = 0;
        static_assert(sizeof(u) == sizeof(v), "float is 32 bits");
        std::memcpy(&u, &v, sizeof(u));
        out[i] = u;
    };
    for (int l = 0; l < kVsmMaxLevels; ++l) {
        glm::mat4 m(0.0f);
        if (l < s.layout.level_count) {
            const VsmMatrix rel = vsm_relative_matrix(s.levels[l].world_to_uv, anchor);
            if (rel.status != Status::Ok) {
                r.status = rel.status;
                r.detail = rel.status == Status::NonFinite ? "anchor: NaN or Inf" : "anchor: a level's matrix beyond float relative to it";
                return r;
            }
            m = rel.matrix;
        }
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) put_float(std::size_t(l * 16 + c * 4 + k), m[c][k]);
        const bool used = l < s.layout.level_count;
        out[256 + 4 * l + 0] = used ? std::uint32_t(s.levels[l].origin_mod_x) : 0u;
        out[256 + 4 * l + 1] = used ? std::uint32_t(s.levels[l].origin_mod_y) : 0u;
        out[256 + 4 * l + 2] = out[256 + 4 * l + 3] = 0u;
    }
    out[320] = std::uint32_t(s.layout.level_count);
    out[321] = std::uint32_t(s.pages_per_side);
    out[322] = std::uint32_t(s.layout.page_texels);
    out[323] = std::uint32_t(s.layout.pool_columns);
    out[324] = s.layout.clip_depth == ClipDepth::ZeroToOne ? 1u : 0u;
    out[325] = s.layout.reversed_z ? 1u : 0u;
    out[326] = detail::vsm_directional(s) ? 1u : 0u;
    out[327] = 0u;
    put_float(328, detail::vsm_directional(s) ? float(s.layout.level0_extent_world / double(s.layout.virtual_texels)) : 0.0f);
    out[329] = out[330] = out[331] = 0u;
    for (std::size_t i = 0; i < s.page_table.size(); ++i) out[kVsmGpuHeaderWords + i] = s.page_table[i];
    r.count = r.needed;
    r.status = Status::Ok;
    return r;
}

/// The page a pool slot holds now (vsm_slot_page).
struct VsmSlotPage {
    Status status = Status::NotRun;
    const char* detail = nullptr;  ///< where a non-Ok status came from: "field: what is wrong" (a static string; nullptr when Ok)
    bool resident = false;           ///< the slot holds a page (false: free; `page` unset)
    bool current = false;            ///< its content is current (kVsmPageValid); false: stale
    bool on_window = false;          ///< the page is on its level's current window (x, y valid)
    VsmPageRender page;              ///< level, x, y, slot, atlas origin and view_proj, as vsm_plan lists it
};

/// The page held by pool slot `slot`, with the matrix it is rendered with now: for re-rendering a
/// resident page (a full re-render of the pool to check a kept one, a debug view). InvalidArgument
/// for an uninitialized state, a state no plan has placed, or slot >= pool_pages.
inline VsmSlotPage vsm_slot_page(const VsmState& s, std::uint32_t slot) {
    VsmSlotPage r;
    const char* why = detail::vsm_unplaced(s);
    if (!why && slot >= s.slots.size()) why = "slot: >= layout.pool_pages";
    if (why) {
        r.status = Status::InvalidArgument;
        r.detail = why;
        return r;
    }
    const VsmSlot& e = s.slots[slot];
    r.status = Status::Ok;
    if (!e.resident) return r;
    r.resident = true;
    const std::uint32_t t = s.page_table[detail::vsm_entry_abs(s, int(e.level), e.x, e.y)];
    r.current = t == (kVsmPageValid | slot);
    const std::int64_t px = e.x - s.origin_x[e.level], py = e.y - s.origin_y[e.level];
    r.on_window = px >= 0 && py >= 0 && px < s.pages_per_side && py < s.pages_per_side;
    r.page.level = e.level;
    r.page.x = r.on_window ? std::uint32_t(px) : 0u;
    r.page.y = r.on_window ? std::uint32_t(py) : 0u;
    r.page.slot = slot;
    r.page.atlas_x = int(slot % std::uint32_t(s.layout.pool_columns)) * s.layout.page_texels;
    r.page.atlas_y = int(slot / std::uint32_t(s.layout.pool_columns)) * s.layout.page_texels;
    r.page.view_proj = detail::vsm_page_matrix(s, int(e.level), e.x, e.y);
    return r;
}

namespace detail {
/// The layout's first invalid field ("layout.field: what is wrong"), nullptr when valid (finite values assumed).
inline const char* vsm_check_layout(const VsmLayout& L) {
    if (L.page_texels < 8 || L.page_texels > 4096) return "layout.page_texels: outside 8..4096";
    if (L.virtual_texels < 2 * L.page_texels || L.virtual_texels % L.page_texels != 0 || L.virtual_texels / L.page_texels > 4096)
        return "layout.virtual_texels: not 2..4096 whole pages";
    if (L.level_count < 1 || L.level_count > kVsmMaxLevels) return "layout.level_count: outside 1..kVsmMaxLevels";
    if (L.pool_pages < 1 || L.pool_pages > kVsmMaxPoolPages) return "layout.pool_pages: outside 1..kVsmMaxPoolPages";
    if (L.pool_columns < 0) return "layout.pool_columns: < 0";
    if (!(L.level0_extent_world >= 1e-30) || !(L.level0_extent_world <= 1e30)) return "layout.level0_extent_world: outside [1e-30, 1e30]";
    if (!(L.depth_range_world >= 1e-30) || !(L.depth_range_world <= 1e30)) return "layout.depth_range_world: outside [1e-30, 1e30]";
    if (L.spot_near_world <= 0.0) return "layout.spot_near_world: <= 0";
    if (L.spot_far_world <= L.spot_near_world) return "layout.spot_far_world: not beyond spot_near_world";
    return nullptr;
}
}  // namespace detail

/// Validates the layout and sizes the state: page table, request stamps, pool slots, LRU list.
/// Allocates (once; vsm_plan never does). Any previous content of `state` is dropped.
inline VsmInit vsm_state_init(const VsmLayout& layout, VsmState& state) {
    VsmInit r;
    state = VsmState();
    const VsmLayout& L = layout;
    if (!std::isfinite(L.level0_extent_world) || !std::isfinite(L.depth_range_world) ||
        !std::isfinite(L.spot_near_world) || !std::isfinite(L.spot_far_world)) {
        r.status = Status::NonFinite;
        r.detail = "layout: NaN or Inf in level0_extent_world, depth_range_world, spot_near_world or spot_far_world";
        return r;
    }
    r.detail = detail::vsm_check_layout(L);
    if (r.detail) {
        r.status = Status::InvalidArgument;
        return r;
    }
    const std::size_t n = std::size_t(L.virtual_texels / L.page_texels);
    const std::size_t entries = std::size_t(L.level_count) * n * n;
    if (entries > kVsmMaxTableEntries) {
        r.status = Status::InvalidArgument;
        r.detail = "layout: level_count * (virtual_texels / page_texels)^2 above kVsmMaxTableEntries";
        return r;
    }
    state.layout = L;
    if (state.layout.pool_columns == 0)
        state.layout.pool_columns = int(std::ceil(std::sqrt(double(L.pool_pages)) - 1e-9));
    state.pages_per_side = int(n);
    state.page_table.assign(entries, 0u);
    state.request_stamp.assign(entries, 0u);
    state.slots.assign(std::size_t(L.pool_pages), VsmSlot());
    state.free_slots.resize(std::size_t(L.pool_pages));
    // free list popped from the back: slot 0 first
    for (std::size_t i = 0; i < state.free_slots.size(); ++i)
        state.free_slots[i] = std::uint32_t(state.free_slots.size() - 1 - i);
    state.free_count = state.free_slots.size();
    state.work.assign(entries, 0u);
    state.work_next.assign(entries, kVsmNone);
    state.initialized = true;
    r.table_entries = entries;
    r.bytes = sizeof(VsmState) + entries * 4 * sizeof(std::uint32_t) +
              std::size_t(L.pool_pages) * (sizeof(VsmSlot) + sizeof(std::uint32_t));
    r.status = Status::Ok;
    return r;
}

namespace detail {

/// Validates the frame (no state change). Returns Ok or the error, with its detail in `why`.
inline Status vsm_check_frame(const VsmState& s, const VsmFrame& f, const VsmPageRender* pages, std::size_t capacity,
                              const char*& why) {
    auto fail = [&why](Status st, const char* w) {
        why = w;
        return st;
    };
    if (!s.initialized) return fail(Status::InvalidArgument, "s: not initialized (vsm_state_init)");
    const glm::vec4 L = f.light_position;
    if (!std::isfinite(L.x) || !std::isfinite(L.y) || !std::isfinite(L.z) || !std::isfinite(L.w))
        return fail(Status::InvalidLight, "f.light_position: NaN or Inf");
    if (L.w < 0.0f) return fail(Status::InvalidLight, "f.light_position: w < 0");
    if (L.x == 0.0f && L.y == 0.0f && L.z == 0.0f) return fail(Status::InvalidLight, "f.light_position: xyz zero");
    if (L.w > 0.0f) {
        const float a = f.spot_cone_half_angle_radians;
        const glm::vec3 d = f.spot_direction;
        if (!std::isfinite(a)) return fail(Status::NonFinite, "f.spot_cone_half_angle_radians: NaN or Inf");
        if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) return fail(Status::NonFinite, "f.spot_direction: NaN or Inf");
        if (!(a > 0.0f && a <= 1.5f)) return fail(Status::InvalidLight, "f.spot_cone_half_angle_radians: outside (0, 1.5]");
        if (glm::length(glm::dvec3(d)) < 1e-12) return fail(Status::InvalidLight, "f.spot_direction: zero");
        if (s.layout.level_count != 1) return fail(Status::InvalidLight, "layout.level_count: not 1 for a spot light");
    }
    if (!std::isfinite(f.camera_position.x) || !std::isfinite(f.camera_position.y) || !std::isfinite(f.camera_position.z))
        return fail(Status::NonFinite, "f.camera_position: NaN or Inf");
    if (f.requests == nullptr && f.request_count != 0) return fail(Status::InvalidArgument, "f.requests: null with request_count > 0");
    if (f.moved_casters == nullptr && f.moved_caster_count != 0)
        return fail(Status::InvalidArgument, "f.moved_casters: null with moved_caster_count > 0");
    if (pages == nullptr) return fail(Status::InvalidArgument, "pages: null");
    if (capacity < std::size_t(s.layout.pool_pages)) return fail(Status::InvalidArgument, "capacity: below layout.pool_pages");
    const std::uint32_t n = std::uint32_t(s.pages_per_side), levels = std::uint32_t(s.layout.level_count);
    for (std::size_t i = 0; i < f.request_count; ++i) {
        const VsmPageRequest& q = f.requests[i];
        if (q.level >= levels || q.x >= n || q.y >= n)
            return fail(Status::IndexOutOfRange, "f.requests: a level or page outside the layout");
    }
    for (std::size_t i = 0; i < f.moved_caster_count; ++i)
        if (!vsm_box_finite(f.moved_casters[i].bounds) || !vsm_box_finite(f.moved_casters[i].previous_bounds))
            return fail(Status::NonFinite, "f.moved_casters: NaN or Inf in bounds or previous_bounds");
    // directional: every window origin must stay exact in double and int64
    if (L.w == 0.0f) {
        glm::dvec3 ax, ay, az;
        vsm_light_basis(glm::dvec3(L), ax, ay, az);
        const double top = s.layout.level0_extent_world * std::ldexp(1.0, s.layout.level_count - 1) / double(n);
        const double fine = s.layout.level0_extent_world / double(n);
        const double span = std::fabs(glm::dot(f.camera_position, ax)) + std::fabs(glm::dot(f.camera_position, ay));
        // the page grid and the depth center in units of a page / of the depth range stay exact
        if (!(span / fine < 4e15) || !std::isfinite(top) ||
            !(std::fabs(glm::dot(f.camera_position, az)) / s.layout.depth_range_world < 1e15))
            return fail(Status::Overflow, "f.camera_position: 4e15 level-0 pages or 1e15 depth ranges from the origin");
    }
    return Status::Ok;
}

/// Places the levels for this frame's light and camera; invalidates or frees what changed.
inline void vsm_place_levels(VsmState& s, const VsmFrame& f, VsmPlan& p) {
    const bool same_light = s.has_light && s.light_position == f.light_position &&
                            (f.light_position.w == 0.0f || (s.spot_direction == f.spot_direction &&
                                                             s.spot_cone_half_angle_radians == f.spot_cone_half_angle_radians));
    if (!same_light) {
        if (s.lru_head != kVsmNone) p.everything_invalidated = true;
        vsm_free_all(s);  // new page grid: nothing resident means anything
        s.light_position = f.light_position;
        s.spot_direction = f.spot_direction;
        s.spot_cone_half_angle_radians = f.spot_cone_half_angle_radians;
    }
    const std::int64_t n = s.pages_per_side;
    if (f.light_position.w > 0.0f) {
        const glm::dvec3 pos = glm::dvec3(f.light_position) / double(f.light_position.w);
        glm::dvec3 ax, ay, az;
        vsm_light_basis(-glm::dvec3(f.spot_direction), ax, ay, az);
        glm::dmat4 view(1.0);
        for (int c = 0; c < 3; ++c) { view[c][0] = ax[c]; view[c][1] = ay[c]; view[c][2] = az[c]; }
        view[3] = glm::dvec4(-glm::dot(ax, pos), -glm::dot(ay, pos), -glm::dot(az, pos), 1.0);
        const double t = 1.0 / std::tan(double(f.spot_cone_half_angle_radians));
        const double zn = s.layout.spot_near_world, zf = s.layout.spot_far_world;
        glm::dmat4 proj(0.0);
        proj[0][0] = t;
        proj[1][1] = t;
        proj[2][3] = -1.0;
        // depth t in [0, 1] from near to far (reversed: 1 to 0), then the clip convention
        double a = zf / (zn - zf), b = zn * zf / (zn - zf);  // z_ndc01 = (a z + b) / -z, z < 0 in view
        if (s.layout.reversed_z) { a = -a - 1.0; b = -b; }
        if (s.layout.clip_depth == ClipDepth::NegativeOneToOne) { a = 2.0 * a + 1.0; b = 2.0 * b; }
        proj[2][2] = a;
        proj[3][2] = b;
        s.axis_x = ax; s.axis_y = ay; s.axis_z = az;
        s.spot_view_proj = proj * view;
        s.origin_x[0] = s.origin_y[0] = 0;
        glm::dmat4 bias(0.5);
        bias[2][2] = 1.0;
        bias[3] = glm::dvec4(0.5, 0.5, 0.0, 1.0);
        s.levels[0].world_to_uv = bias * s.spot_view_proj;
        s.levels[0].origin_mod_x = s.levels[0].origin_mod_y = 0;
        s.levels[0].page_world = 0.0;
        s.has_light = true;
        return;
    }
    vsm_light_basis(glm::dvec3(f.light_position), s.axis_x, s.axis_y, s.axis_z);
    const double step = 0.5 * s.layout.depth_range_world;
    const double center = step * std::floor(glm::dot(f.camera_position, s.axis_z) / step + 0.5);
    if (same_light && center != s.depth_center && s.lru_head != kVsmNone) {
        vsm_stale_all(s);
        p.everything_invalidated = true;
    }
    s.depth_center = center;
    for (int l = 0; l < s.layout.level_count; ++l) {
        const double page = vsm_page_world(s, l);
        // snapped in double: the camera's page on this level, the window centered on it
        const std::int64_t nx = std::int64_t(std::floor(glm::dot(f.camera_position, s.axis_x) / page)) - n / 2;
        const std::int64_t ny = std::int64_t(std::floor(glm::dot(f.camera_position, s.axis_y) / page)) - n / 2;
        if (same_light && (nx != s.origin_x[l] || ny != s.origin_y[l]))
            p.scrolled_out += vsm_scroll_level(s, l, s.origin_x[l], s.origin_y[l], nx, ny);
        s.origin_x[l] = nx;
        s.origin_y[l] = ny;
        VsmLevelLookup& lk = s.levels[l];
        glm::dmat4 bias(0.5);
        bias[2][2] = 1.0;
        bias[3] = glm::dvec4(0.5, 0.5, 0.0, 1.0);
        lk.world_to_uv = bias * vsm_ortho(s, page, nx, ny, double(n));
        lk.origin_mod_x = int(vsm_floor_mod(nx, n));
        lk.origin_mod_y = int(vsm_floor_mod(ny, n));
        lk.page_world = page;
    }
    s.has_light = true;
}

/// Appends a packed page to the work list and to its level's list.
inline void vsm_work_append(VsmState& s, std::uint32_t packed) {
    const std::uint32_t i = std::uint32_t(s.work_count++), l = vsm_unpack_level(packed);
    s.work[i] = packed;
    s.work_next[i] = kVsmNone;
    if (s.level_tail[l] == kVsmNone) s.level_head[l] = i; else s.work_next[s.level_tail[l]] = i;
    s.level_tail[l] = i;
}

/// Distinct requests into s.work (packed), stamped in request_stamp; returns the per-level counts.
inline void vsm_collect(VsmState& s, const VsmFrame& f, std::size_t per_level[kVsmMaxLevels]) {
    s.work_count = 0;
    for (int l = 0; l < kVsmMaxLevels; ++l) s.level_head[l] = s.level_tail[l] = kVsmNone;
    for (std::size_t i = 0; i < f.request_count; ++i) {
        const VsmPageRequest& q = f.requests[i];
        const std::size_t e = vsm_table_index(s, q.level, q.x, q.y);
        if (s.request_stamp[e] == s.frame) continue;
        s.request_stamp[e] = s.frame;
        vsm_work_append(s, vsm_pack(q.level, q.x, q.y));
        ++per_level[q.level];
    }
}

/// Pool too small: replaces requests of the finest level by their parents (one level coarser), page
/// by page (first the pages whose parent is requested anyway: each saves a page; then the others, in
/// request order), then the next level, until the distinct pages fit or only the coarsest level is
/// left. Returns the finest level still holding requests; p.fallback counts the replaced original
/// requests.
inline int vsm_coarsen(VsmState& s, std::size_t per_level[kVsmMaxLevels], std::size_t total, VsmPlan& p) {
    const std::size_t pool = std::size_t(s.layout.pool_pages), originals = s.work_count;
    const int levels = s.layout.level_count;
    int finest = 0;
    while (finest < levels && per_level[finest] == 0) ++finest;
    while (total > pool && finest < levels - 1) {
        const int f = finest;
        for (int pass = 0; pass < 2 && total > pool; ++pass) {
            for (std::uint32_t i = s.level_head[f]; i != kVsmNone && total > pool; i = s.work_next[i]) {
                const std::uint32_t w = s.work[i];
                if (w == kVsmTombstone) continue;
                const std::int64_t ax = s.origin_x[f] + std::int64_t(vsm_unpack_x(w));
                const std::int64_t ay = s.origin_y[f] + std::int64_t(vsm_unpack_y(w));
                // the parent: the coarser page grid is the finer one halved (same world anchor);
                // it lies on the coarser window (which holds the finer one)
                const std::int64_t px = vsm_floor_div(ax, 2) - s.origin_x[f + 1];
                const std::int64_t py = vsm_floor_div(ay, 2) - s.origin_y[f + 1];
                const std::size_t e = vsm_table_index(s, std::uint32_t(f + 1), std::uint32_t(px), std::uint32_t(py));
                const bool present = s.request_stamp[e] == s.frame;
                if (pass == 0 && !present) continue;
                s.work[i] = kVsmTombstone;
                --per_level[f];
                if (i < originals) ++p.fallback;
                if (present) {
                    --total;
                } else {
                    s.request_stamp[e] = s.frame;
                    vsm_work_append(s, vsm_pack(std::uint32_t(f + 1), std::uint32_t(px), std::uint32_t(py)));
                    ++per_level[f + 1];
                }
            }
        }
        if (per_level[f] != 0) break;  // level f is mapped in part
        ++finest;
    }
    return finest;
}

/// Lists slot i to render as page (level, x, y) of the window.
inline void vsm_emit(VsmState& s, std::uint32_t i, std::uint32_t level, std::uint32_t x, std::uint32_t y,
                     VsmPageRender* pages, VsmPlan& p) {
    VsmSlot& e = s.slots[i];
    VsmPageRender& r = pages[p.count];
    r.level = level;
    r.x = x;
    r.y = y;
    r.slot = i;
    const int cols = s.layout.pool_columns;
    r.atlas_x = int(i % std::uint32_t(cols)) * s.layout.page_texels;
    r.atlas_y = int(i / std::uint32_t(cols)) * s.layout.page_texels;
    r.view_proj = vsm_page_matrix(s, int(level), e.x, e.y);
    e.render_frame = s.frame;
    e.render_index = std::uint32_t(p.count);
    ++p.count;
}

}  // namespace detail

/// Plans one frame: places the clipmap levels on the camera (snapped to whole pages, in double),
/// frees pages that scrolled out, makes stale the pages moved casters' old and new bounds overlap,
/// keeps requested pages that are resident and current, gives the others a slot (free ones first,
/// then the least recently requested page's), and lists the pages to render in `pages`.
/// `pages` holds `capacity` elements; it needs layout.pool_pages (checked: InvalidArgument).
/// Cost: O(requests + pages the moved casters' boxes overlap + pages that scrolled out); a light
/// change or a depth step costs O(resident pages). Never allocates.
/// Status: Ok; Overflow when the camera is 4e15 level-0 pages or 1e15 depth ranges from the origin;
/// BufferTooSmall when the distinct requested pages exceed the pool (`needed` says how
/// many): the plan is applied anyway, finest levels falling back to coarser ones (VsmPlan::fallback,
/// unmapped); on any other status the state is unchanged.
inline VsmPlan vsm_plan(VsmState& s, const VsmFrame& f, VsmPageRender* pages, std::size_t capacity) {
    VsmPlan p;
    p.status = detail::vsm_check_frame(s, f, pages, capacity, p.detail);
    if (p.status != Status::Ok) return p;
    ++s.frame;
    if (s.frame == 0) {  // wrapped: stamps of 2^32 frames ago would read as this frame
        for (auto& t : s.request_stamp) t = 0u;
        for (auto& e : s.slots) e.render_frame = e.last_request = 0u;
        s.frame = 1;
    }
    detail::vsm_place_levels(s, f, p);
    std::size_t resident = std::size_t(s.layout.pool_pages) - s.free_count;
    for (std::size_t i = 0; i < f.moved_caster_count; ++i) {
        const VsmCasterMove& m = f.moved_casters[i];
        if (!detail::vsm_box_empty(m.previous_bounds)) p.invalidated += detail::vsm_invalidate_box(s, m.previous_bounds, resident);
        if (!detail::vsm_box_empty(m.bounds)) p.invalidated += detail::vsm_invalidate_box(s, m.bounds, resident);
    }
    std::size_t per_level[kVsmMaxLevels] = {};
    detail::vsm_collect(s, f, per_level);
    p.requested = p.needed = s.work_count;
    p.finest_level = detail::vsm_coarsen(s, per_level, s.work_count, p);
    // 1. requested and resident: most recently requested now, re-render if stale
    for (std::size_t k = 0; k < s.work_count; ++k) {
        const std::uint32_t w = s.work[k];
        if (w == detail::kVsmTombstone) continue;
        std::uint32_t& t = s.page_table[vsm_table_index(s, detail::vsm_unpack_level(w), detail::vsm_unpack_x(w), detail::vsm_unpack_y(w))];
        if (t == 0u) continue;
        const std::uint32_t i = t & kVsmSlotMask;
        detail::vsm_lru_unlink(s, i);
        detail::vsm_lru_push_front(s, i);
        s.slots[i].last_request = s.frame;
        if (t & kVsmPageValid) { ++p.kept; continue; }
        t = kVsmPageValid | i;
        ++p.rerendered;
        detail::vsm_emit(s, i, detail::vsm_unpack_level(w), detail::vsm_unpack_x(w), detail::vsm_unpack_y(w), pages, p);
    }
    // 2. requested and missing: a free slot, else the least recently requested page's
    for (std::size_t k = 0; k < s.work_count; ++k) {
        const std::uint32_t w = s.work[k];
        if (w == detail::kVsmTombstone) continue;
        const std::uint32_t level = detail::vsm_unpack_level(w), x = detail::vsm_unpack_x(w), y = detail::vsm_unpack_y(w);
        std::uint32_t& t = s.page_table[vsm_table_index(s, level, x, y)];
        if (t != 0u) continue;
        if (s.free_count == 0) {
            const std::uint32_t victim = s.lru_tail;
            if (victim == kVsmNone || s.slots[victim].last_request == s.frame) { ++p.unmapped; continue; }
            detail::vsm_free_slot(s, victim);
            ++p.evicted;
        }
        const std::uint32_t i = s.free_slots[--s.free_count];
        VsmSlot& e = s.slots[i];
        e.level = level;
        e.x = s.origin_x[level] + std::int64_t(x);
        e.y = s.origin_y[level] + std::int64_t(y);
        e.resident = true;
        e.last_request = s.frame;
        detail::vsm_lru_push_front(s, i);
        t = kVsmPageValid | i;
        ++p.allocated;
        detail::vsm_emit(s, i, level, x, y, pages, p);
    }
    p.status = p.needed > std::size_t(s.layout.pool_pages) ? Status::BufferTooSmall : Status::Ok;
    if (p.status != Status::Ok) p.detail = "layout.pool_pages: fewer than the requested pages (coarser pages stand in: fallback)";
    return p;
}

/// The casters to draw into each page of the last plan (CPU culling): for page i of `pages` (count
/// from that plan), `first[i]` and `counts[i]` delimit its indices into `bounds` (caster_count boxes
/// of 6 floats, world) in `indices`. A caster is listed for a page when its box, projected along the
/// light, overlaps the page (any depth). `first` and `counts` hold `count` uint32 each; `indices`
/// holds `index_capacity` uint32 elements; it needs the sum of counts (`needed`; BufferTooSmall
/// writes counts and first as if it fitted, no indices). Cost: O(caster_count * levels + pages the
/// boxes overlap). Empty boxes are never listed; non-finite boxes give NonFinite.
inline VsmPageCasters vsm_page_casters(const VsmState& s, const VsmPageRender* pages, std::size_t count, const float* bounds,
                                       std::size_t caster_count, std::uint32_t* first, std::uint32_t* counts,
                                       std::uint32_t* indices, std::size_t index_capacity) {
    VsmPageCasters r;
    const char* why = detail::vsm_unplaced(s);
    if (!why)
        why = (pages == nullptr && count != 0)                         ? "pages: null with count > 0"
              : (bounds == nullptr && caster_count != 0)               ? "bounds: null with caster_count > 0"
              : ((first == nullptr || counts == nullptr) && count != 0) ? "first, counts: null with count > 0"
              : (indices == nullptr && index_capacity != 0)            ? "indices: null with index_capacity > 0"
              : caster_count > 0xFFFFFFFFu                             ? "caster_count: beyond uint32 indices"
              : count > s.slots.size()                                 ? "count: above layout.pool_pages"
                                                                       : nullptr;
    if (why) {
        r.status = Status::InvalidArgument;
        r.detail = why;
        return r;
    }
    for (std::size_t i = 0; i < count; ++i) {
        const VsmPageRender& q = pages[i];
        if (q.slot >= s.slots.size() || s.slots[q.slot].render_frame != s.frame || s.slots[q.slot].render_index != i ||
            q.level >= std::uint32_t(s.layout.level_count)) {
            r.status = Status::InvalidArgument;
            r.detail = "pages: not the last vsm_plan's list";
            return r;
        }
        counts[i] = 0;
    }
    for (std::size_t c = 0; c < caster_count; ++c)
        if (!detail::vsm_box_finite(bounds + 6 * c)) {
            r.status = Status::NonFinite;
            r.detail = "bounds: NaN or Inf";
            return r;
        }
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            std::size_t acc = 0;
            for (std::size_t i = 0; i < count; ++i) { first[i] = std::uint32_t(acc); acc += counts[i]; counts[i] = 0; }
            r.needed = acc;
            if (acc > index_capacity) {
                for (std::size_t i = 0; i < count; ++i) counts[i] = (i + 1 < count ? first[i + 1] : std::uint32_t(acc)) - first[i];
                r.status = Status::BufferTooSmall;
                r.detail = "index_capacity: below the sum of counts (needed)";
                return r;
            }
        }
        for (std::size_t c = 0; c < caster_count; ++c) {
            const float* b = bounds + 6 * c;
            if (detail::vsm_box_empty(b)) continue;
            for (int l = 0; l < s.layout.level_count; ++l) {
                std::int64_t q[4];
                if (!detail::vsm_box_pages(s, l, b, q)) continue;
                const std::uint64_t area = std::uint64_t(q[2] - q[0] + 1) * std::uint64_t(q[3] - q[1] + 1);
                auto visit = [&](std::size_t i) {
                    if (pass == 1) indices[first[i] + counts[i]] = std::uint32_t(c);
                    ++counts[i];
                };
                if (area <= count) {
                    for (std::int64_t y = q[1]; y <= q[3]; ++y)
                        for (std::int64_t x = q[0]; x <= q[2]; ++x) {
                            const std::uint32_t t = s.page_table[detail::vsm_entry_abs(s, l, x, y)];
                            if (t == 0u) continue;
                            const VsmSlot& e = s.slots[t & kVsmSlotMask];
                            if (e.render_frame == s.frame && e.x == x && e.y == y && int(e.level) == l) visit(e.render_index);
                        }
                } else {
                    for (std::size_t i = 0; i < count; ++i) {
                        const VsmSlot& e = s.slots[pages[i].slot];
                        if (int(e.level) == l && e.x >= q[0] && e.x <= q[2] && e.y >= q[1] && e.y <= q[3]) visit(i);
                    }
                }
            }
        }
    }
    r.count = r.needed;
    r.status = Status::Ok;
    return r;
}

}  // namespace shadowkit

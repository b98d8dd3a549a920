// libFuzzer target for shadowkit/virtual_shadow_map.hpp: vsm_state_init on a decoded layout, then a
// few frames of vsm_plan with requests (in and out of range, duplicated), moved casters (raw or
// quantized boxes, empty ones), camera moves (sub-page, whole pages, jumps, raw doubles) and lights
// (directional, spot, raw) from the fuzzer, then vsm_page_casters on the frame's pages; and
// vsm_requests_from_bitmask on a fuzzed mask.
// Traps on: a plan that is Ok or BufferTooSmall whose table maps two virtual pages to one physical
// page, an entry whose slot does not hold that page, a requested page neither mapped nor reported
// (no fallback and no unmapped count), count > pool pages, a non-finite page matrix, BufferTooSmall
// with needed <= pool, a rejected frame that changed the state, caster lists beyond their capacity.
#include <shadowkit/virtual_shadow_map.hpp>

#include "fuzz_input.hpp"

#include <cmath>
#include <cstring>
#include <cstddef>
#include <cstdint>
#include <vector>

using shadowkit_fuzz::FuzzInput;
using shadowkit_fuzz::check;
using shadowkit_fuzz::check_detail;

namespace {

void decode_box(FuzzInput& r, bool raw, float* b) {
    for (int i = 0; i < 6; ++i) b[i] = raw ? r.f32() : r.quantized(0.5f);
}

void check_table(const shadowkit::VsmState& s) {
    using namespace shadowkit;
    static std::vector<std::uint8_t> seen;
    seen.assign(s.slots.size(), 0);
    std::size_t nonzero = 0;
    const int n = s.pages_per_side;
    for (int l = 0; l < s.layout.level_count; ++l)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const std::uint32_t t = s.page_table[vsm_table_index(s, std::uint32_t(l), std::uint32_t(x), std::uint32_t(y))];
                if (t == 0u) continue;
                ++nonzero;
                check(((t & kVsmPageValid) != 0) != ((t & kVsmPageAllocated) != 0));
                const std::uint32_t slot = t & kVsmSlotMask;
                check(slot < s.slots.size());
                check(seen[slot] == 0);  // never two virtual pages on one physical page
                seen[slot] = 1;
                const VsmSlot& e = s.slots[slot];
                check(e.resident && int(e.level) == l && e.x == s.origin_x[l] + x && e.y == s.origin_y[l] + y);
            }
    check(nonzero + s.free_count == s.slots.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace shadowkit;
    FuzzInput r(data, size);
    VsmLayout L;
    L.page_texels = 8;
    const int per_side = r.range<int>(1, 12);
    L.virtual_texels = (r.u8() % 16 == 0) ? r.range<int>(-4, 200) : 8 * per_side;
    L.level_count = r.range<int>(0, 17);
    L.pool_pages = r.range<int>(0, 80);
    L.pool_columns = r.range<int>(-1, 9);
    L.level0_extent_world = (r.u8() % 8 == 0) ? double(r.f32()) : double(r.range<int>(1, 64));
    L.depth_range_world = (r.u8() % 8 == 0) ? double(r.f32()) : 200.0;
    L.clip_depth = r.boolean() ? ClipDepth::ZeroToOne : ClipDepth::NegativeOneToOne;
    L.reversed_z = r.boolean();
    VsmState s;
    const VsmInit init = vsm_state_init(L, s);
    check_detail(init);
    if (init.status != Status::Ok) return 0;
    const std::uint32_t n = std::uint32_t(s.pages_per_side), levels = std::uint32_t(s.layout.level_count);
    {  // a request bitmask from the fuzzer
        std::vector<std::uint32_t> mask(vsm_bitmask_words(s));
        for (std::uint32_t& w : mask) w = r.u8() % 4 == 0 ? r.u32() : 0u;
        std::vector<VsmPageRequest> out(r.range<std::size_t>(0, 40));
        const VsmRequestList rl = vsm_requests_from_bitmask(s, mask.data(), mask.size(), out.empty() ? nullptr : out.data(), out.size());
        check(rl.count <= out.size() && rl.count <= rl.needed);
        check_detail(rl);
        check(rl.status == (rl.count == rl.needed ? Status::Ok : Status::BufferTooSmall));
        for (std::size_t i = 0; i < rl.count; ++i)
            check(out[i].level < std::uint32_t(s.layout.level_count) && out[i].x < std::uint32_t(s.pages_per_side) &&
                  out[i].y < std::uint32_t(s.pages_per_side));
    }
    std::vector<VsmPageRender> pages(std::size_t(s.layout.pool_pages) + 1);
    glm::dvec3 cam(0.0);
    glm::vec4 light(0.3f, 1.0f, 0.2f, 0.0f);
    const int frames = r.range<int>(1, 6);
    for (int fr = 0; fr < frames && r.remaining() > 0; ++fr) {
        const std::uint8_t mode = r.u8();
        switch (mode % 6) {
        case 0: break;
        case 1: cam += glm::dvec3(r.quantized(0.25f), r.quantized(0.25f), r.quantized(0.25f)); break;
        case 2: cam += glm::dvec3(r.mostly_within(1e3f), r.mostly_within(1e3f), r.mostly_within(1e3f)); break;
        case 3: cam = glm::dvec3(r.f64(), r.f64(), r.f64()); break;
        case 4: light = glm::vec4(r.quantized(0.25f), r.quantized(0.25f), r.quantized(0.25f), 0.0f); break;
        default: light = r.vec4(); break;
        }
        VsmFrame f;
        f.camera_position = cam;
        f.light_position = light;
        f.spot_direction = glm::vec3(r.quantized(0.25f), r.quantized(0.25f), r.quantized(0.25f));
        f.spot_cone_half_angle_radians = r.boolean() ? r.f32() : float(r.range<int>(1, 15)) * 0.1f;
        std::vector<VsmPageRequest> req(r.range<std::size_t>(0, 64));
        for (VsmPageRequest& q : req) {
            const bool wild = r.u8() % 32 == 0;
            q.level = wild ? r.u32() : r.range<std::uint32_t>(0, levels - 1);
            q.x = wild ? r.u32() : r.range<std::uint32_t>(0, n - 1);
            q.y = wild ? r.u32() : r.range<std::uint32_t>(0, n - 1);
        }
        std::vector<VsmCasterMove> moves(r.range<std::size_t>(0, 4));
        const bool raw = r.u8() % 8 == 0;
        for (VsmCasterMove& m : moves) {
            decode_box(r, raw, m.previous_bounds);
            decode_box(r, raw, m.bounds);
        }
        f.requests = req.empty() && r.boolean() ? nullptr : req.data();
        f.request_count = req.size();
        f.moved_casters = moves.empty() ? nullptr : moves.data();
        f.moved_caster_count = moves.size();
        const std::size_t cap = r.u8() % 16 == 0 ? pages.size() - 2 : pages.size();
        const std::uint32_t frame_before = s.frame;
        const std::size_t free_before = s.free_count;
        const VsmPlan p = vsm_plan(s, f, pages.data(), cap);
        check_detail(p);
        if (p.status != Status::Ok && p.status != Status::BufferTooSmall) {
            check(s.frame == frame_before && s.free_count == free_before && p.count == 0);
            continue;
        }
        check_table(s);
        check(p.count <= std::size_t(s.layout.pool_pages));
        check(p.kept + p.allocated + p.rerendered + p.unmapped <= p.needed);
        if (p.status == Status::BufferTooSmall) check(p.needed > std::size_t(s.layout.pool_pages));
        else check(p.needed <= std::size_t(s.layout.pool_pages) && p.fallback == 0 && p.unmapped == 0);
        for (std::size_t i = 0; i < p.count; ++i) {
            const VsmPageRender& g = pages[i];
            check(g.level < levels && g.x < n && g.y < n && g.slot < std::uint32_t(s.layout.pool_pages));
            check(s.page_table[vsm_table_index(s, g.level, g.x, g.y)] == (kVsmPageValid | g.slot));
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 4; ++k) check(std::isfinite(g.view_proj[c][k]));
        }
        // every requested page is mapped at its level, or the plan reports the fallback / holes
        for (const VsmPageRequest& q : req) {
            if (q.level >= levels || q.x >= n || q.y >= n) break;
            const std::uint32_t t = s.page_table[vsm_table_index(s, q.level, q.x, q.y)];
            if ((t & kVsmPageValid) == 0) check(p.fallback > 0 || p.unmapped > 0);
        }
        // CPU culling of the decoded boxes on this frame's pages
        std::vector<float> boxes;
        for (const VsmCasterMove& m : moves) boxes.insert(boxes.end(), m.bounds, m.bounds + 6);
        std::vector<std::uint32_t> first(p.count), counts(p.count), idx(r.range<std::size_t>(0, 64));
        const VsmPageCasters pc = vsm_page_casters(s, pages.data(), p.count, boxes.empty() ? nullptr : boxes.data(), moves.size(),
                                                   first.data(), counts.data(), idx.empty() ? nullptr : idx.data(), idx.size());
        check_detail(pc);
        if (pc.status == Status::Ok) {
            check(pc.count == pc.needed && pc.count <= idx.size());
            for (std::size_t i = 0; i < p.count; ++i) {
                check(std::size_t(first[i]) + counts[i] <= pc.count);
                for (std::uint32_t k = 0; k < counts[i]; ++k) check(idx[first[i] + k] < moves.size());
            }
        } else if (pc.status == Status::BufferTooSmall) {
            check(pc.needed > idx.size() && pc.count == 0);
        }
        // the GPU block around a fuzzed anchor: a copy of the table after the header; Ok only finite
        std::vector<std::uint32_t> block(r.u8() % 8 == 0 ? r.range<std::size_t>(0, 400) : vsm_gpu_block_words(s));
        const glm::dvec3 anchor = r.boolean() ? cam : glm::dvec3(r.f64(), r.f64(), r.f64());
        const VsmGpuBlock gb = vsm_gpu_block(s, anchor, block.empty() ? nullptr : block.data(), block.size());
        check(gb.count <= block.size());
        check_detail(gb);
        if (gb.status == Status::Ok) {
            check(gb.count == vsm_gpu_block_words(s) && gb.needed == gb.count);
            for (std::size_t i = 0; i < 256; ++i) {
                float v = 0.0f;
                std::memcpy(&v, &block[i], 4);
                check(std::isfinite(v));
            }
            for (std::size_t i = 0; i < s.page_table.size(); ++i) check(block[kVsmGpuHeaderWords + i] == s.page_table[i]);
        } else if (gb.status == Status::BufferTooSmall) {
            check(gb.needed > block.size());
        }
        // every slot's page: current ones are where the table says, with finite matrices
        const std::uint32_t probe = r.u32() % (std::uint32_t(s.layout.pool_pages) + 2);
        const VsmSlotPage sp = vsm_slot_page(s, probe);
        check_detail(sp);
        if (probe >= std::uint32_t(s.layout.pool_pages)) check(sp.status == Status::InvalidArgument);
        if (sp.status == Status::Ok && sp.resident && sp.current && sp.on_window) {
            check(s.page_table[vsm_table_index(s, sp.page.level, sp.page.x, sp.page.y)] == (kVsmPageValid | probe));
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 4; ++k) check(std::isfinite(sp.page.view_proj[c][k]));
        }
    }
    return 0;
}

// A HID report-descriptor parser for gamepads (HID 1.11 §6.2.2), short items only, and
// the generic decoder over its fields.
//
//   item prefix   bits 7..4 tag   bits 3..2 type (0 Main, 1 Global, 2 Local)   bits 1..0 size
//                 (size code 3 means 4 bytes); 0xFE starts a long item (skipped).
#include <algorithm>
#include <cmath>

#include "gamepad.h"

namespace rg::viewer::pad {

namespace {

constexpr uint16_t kGenericDesktop = 0x01, kButtonPage = 0x09;
constexpr uint16_t kJoystick = 0x04, kGamepad = 0x05;
constexpr uint16_t kX = 0x30, kY = 0x31, kZ = 0x32, kRx = 0x33, kRy = 0x34, kRz = 0x35, kHat = 0x39;

struct Globals {
    uint16_t usagePage = 0;
    int32_t logicalMin = 0, logicalMax = 0;
    uint32_t reportSize = 0, reportCount = 0;
    uint8_t reportId = 0;
};

bool wanted(uint16_t page, uint16_t usage) {
    if (page == kButtonPage) return usage >= 1 && usage <= 32;
    return page == kGenericDesktop && ((usage >= kX && usage <= kRz) || usage == kHat);
}

}  // namespace

HidDescriptor parseHidDescriptor(std::span<const uint8_t> d) {
    HidDescriptor out;
    Globals g;
    std::vector<Globals> stack;
    std::vector<uint32_t> usages;           // local: full usages (page << 16 | id)
    uint32_t usageMin = 0, usageMax = 0;
    bool haveRange = false;
    std::vector<uint32_t> bitsPerReport(256, 0);
    size_t i = 0;
    while (i < d.size()) {
        const uint8_t prefix = d[i];
        if (prefix == 0xfe) {  // long item: size, tag, data
            if (i + 1 >= d.size()) break;
            i += 3 + size_t(d[i + 1]);
            continue;
        }
        const size_t size = (prefix & 3) == 3 ? 4 : (prefix & 3);
        if (i + 1 + size > d.size()) break;  // truncated: keep what we have
        uint32_t u = 0;
        for (size_t k = 0; k < size; ++k) u |= uint32_t(d[i + 1 + k]) << (8 * k);
        int32_t sv = size == 1 ? int32_t(int8_t(u)) : size == 2 ? int32_t(int16_t(u)) : int32_t(u);
        const uint8_t type = (prefix >> 2) & 3, tag = prefix >> 4;
        i += 1 + size;
        auto fullUsage = [&](uint32_t v) { return size == 4 ? v : (uint32_t(g.usagePage) << 16) | v; };
        if (type == 1) {  // Global
            switch (tag) {
                case 0x0: g.usagePage = uint16_t(u); break;
                case 0x1: g.logicalMin = sv; break;
                case 0x2:
                    g.logicalMax = sv;
                    break;
                case 0x7: g.reportSize = u; break;
                case 0x8:
                    g.reportId = uint8_t(u);
                    out.usesReportIds = true;
                    break;
                case 0x9: g.reportCount = u; break;
                case 0xa:
                    if (stack.size() < 16) stack.push_back(g);
                    break;
                case 0xb:
                    if (!stack.empty()) g = stack.back(), stack.pop_back();
                    break;
                default: break;
            }
        } else if (type == 2) {  // Local
            switch (tag) {
                case 0x0:
                    if (usages.size() < 1024) usages.push_back(fullUsage(u));
                    break;
                case 0x1: usageMin = fullUsage(u), haveRange = true; break;
                case 0x2: usageMax = fullUsage(u), haveRange = true; break;
                default: break;
            }
        } else if (type == 0) {  // Main
            if (tag == 0xa) {  // Collection
                if (u == 0x01 && !usages.empty()) {
                    uint32_t app = usages.back();
                    if ((app >> 16) == kGenericDesktop &&
                        ((app & 0xffff) == kJoystick || (app & 0xffff) == kGamepad))
                        out.isGamepad = true;
                }
            } else if (tag == 0x8) {  // Input
                const bool constant = u & 0x01;
                uint32_t& bits = bitsPerReport[g.reportId];
                // Logical max read as unsigned when the minimum is non-negative and the
                // signed reading went negative (e.g. 0..255 written in one byte as 0xFF).
                int32_t lmax = g.logicalMax;
                if (g.logicalMin >= 0 && lmax < 0 && g.reportSize < 32)
                    lmax = int32_t(uint32_t(lmax) & ((1u << std::min<uint32_t>(g.reportSize, 31)) - 1));
                const uint32_t count = std::min<uint32_t>(g.reportCount, 4096);
                const uint32_t rsize = std::min<uint32_t>(g.reportSize, 32);
                for (uint32_t k = 0; k < count; ++k) {
                    uint32_t usage = 0;
                    if (!usages.empty())
                        usage = usages[std::min<size_t>(k, usages.size() - 1)];
                    else if (haveRange && usageMax >= usageMin)
                        usage = std::min(usageMin + k, usageMax);
                    if (!constant && rsize > 0 && wanted(uint16_t(usage >> 16), uint16_t(usage)) &&
                        out.fields.size() < 256)
                        out.fields.push_back({g.reportId, bits, rsize, uint16_t(usage >> 16),
                                              uint16_t(usage & 0xffff), g.logicalMin, lmax});
                    bits += rsize;
                }
            }
            if (tag == 0x8 || tag == 0x9 || tag == 0xb || tag == 0xa || tag == 0xc) {
                usages.clear();
                haveRange = false;
                usageMin = usageMax = 0;
            }
        }
    }
    return out;
}

std::optional<PadState> decodeGeneric(const HidDescriptor& desc, std::span<const uint8_t> report) {
    if (report.empty() || desc.fields.empty()) return std::nullopt;
    const uint8_t id = desc.usesReportIds ? report[0] : 0;
    std::span<const uint8_t> data = desc.usesReportIds ? report.subspan(1) : report;
    auto read = [&](const HidField& f, int64_t& value) {
        if (uint64_t(f.bitOffset) + f.bitSize > uint64_t(data.size()) * 8) return false;
        uint64_t v = 0;
        for (uint32_t b = 0; b < f.bitSize; ++b) {
            uint32_t bit = f.bitOffset + b;
            v |= uint64_t((data[bit >> 3] >> (bit & 7)) & 1) << b;
        }
        if (f.logicalMin < 0 && f.bitSize < 64 && (v >> (f.bitSize - 1)) & 1)
            value = int64_t(v) - (int64_t(1) << f.bitSize);  // sign-extend
        else
            value = int64_t(v);
        return true;
    };
    auto norm = [](const HidField& f, int64_t v) {
        double lo = f.logicalMin, hi = f.logicalMax;
        if (hi <= lo) return 0.0f;
        return float(std::clamp(2.0 * (double(v) - lo) / (hi - lo) - 1.0, -1.0, 1.0));
    };
    PadState s;
    bool any = false, haveRxRy = false;
    for (const HidField& f : desc.fields)
        if (f.reportId == id && f.usagePage == kGenericDesktop && (f.usage == kRx || f.usage == kRy))
            haveRxRy = true;
    static const uint32_t buttonOrder[14] = {South, East, West, North, L1, R1, L2, R2,
                                             Select, Start, LStick, RStick, Home, Misc};
    for (const HidField& f : desc.fields) {
        if (f.reportId != id) continue;
        int64_t v = 0;
        if (!read(f, v)) continue;
        any = true;
        if (f.usagePage == kButtonPage) {
            if (v && f.usage >= 1 && f.usage <= 14) s.buttons |= buttonOrder[f.usage - 1];
            continue;
        }
        switch (f.usage) {
            case kX: s.lx = norm(f, v); break;
            case kY: s.ly = -norm(f, v); break;
            case kRx: s.rx = norm(f, v); break;
            case kRy: s.ry = -norm(f, v); break;
            case kZ:
                if (!haveRxRy) s.rx = norm(f, v);
                break;
            case kRz:
                if (!haveRxRy) s.ry = -norm(f, v);
                break;
            case kHat: {
                // Logical range of 8 positions (or 4); out of range is the null state.
                int64_t span = int64_t(f.logicalMax) - f.logicalMin + 1;
                if (v >= f.logicalMin && v <= f.logicalMax && (span == 8 || span == 4))
                    s.hat = int((v - f.logicalMin) * (8 / span));
                else
                    s.hat = -1;
                break;
            }
            default: break;
        }
    }
    if (!any) return std::nullopt;
    return s;
}

}  // namespace rg::viewer::pad

// Texture storage and the emulated texture memory (docs/hardware.md, "Texture storage
// and memory").
#include <algorithm>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstring>
#include <string>

#include <tmmintrin.h>

#include "core/error.h"
#include "texunit/texture.h"

namespace rg::tex {

// Bookkeeping shared by a memory and the textures it created, so that a texture that
// outlives its TextureMemory still releases its bytes safely.
struct Texture::Pool {
    uint64_t capacity = 0;
    uint64_t resident = 0;
    // Atomic: a texture nothing samples meanwhile may be uploaded on another thread while
    // the device draws with the others (lightfield's swapped slices), and each draw reads
    // the counter. A sum, so the order of the adds does not matter.
    std::atomic<uint64_t> uploadBytes{0};
};

namespace {

int dimsOf(TextureTarget t) {
    switch (t) {
        case TextureTarget::Texture1D: return 1;
        case TextureTarget::Texture2D: return 2;
        case TextureTarget::Texture3D: return 3;
        case TextureTarget::CubeMap: return 2;
        case TextureTarget::Texture4D: return 4;
    }
    return 2;
}

const char* targetName(TextureTarget t) {
    switch (t) {
        case TextureTarget::Texture1D: return "1D texture";
        case TextureTarget::Texture2D: return "2D texture";
        case TextureTarget::Texture3D: return "3D texture";
        case TextureTarget::CubeMap: return "cube map";
        case TextureTarget::Texture4D: return "4D texture";
    }
    return "texture";
}

}  // namespace

int fullChainLevels(const TextureDesc& d) {
    int m = std::max({d.width, d.height, d.depth, d.size4, 1});
    return std::bit_width(unsigned(m));  // floor(log2 m) + 1
}

Texture::Texture(const TextureDesc& desc, std::shared_ptr<Pool> pool)
    : desc_(desc), pool_(std::move(pool)) {
    dims_ = dimsOf(desc.target);
    faces_ = desc.target == TextureTarget::CubeMap ? 6 : 1;
    const FormatInfo& fi = formatInfo(desc.format);
    singleChannel_ = fi.isDepth || desc.format == TexelFormat::R16F || desc.format == TexelFormat::R32F;
    std::array<int, 4> base{desc.width, desc.height, desc.depth, desc.size4};
    levels_.resize(size_t(desc.levels));
    for (int l = 0; l < desc.levels; ++l) {
        Level& lv = levels_[size_t(l)];
        lv.count = 1;
        for (int d = 0; d < 4; ++d) {
            lv.size[size_t(d)] = d < dims_ ? std::max(1, base[size_t(d)] >> l) : 1;
            lv.count *= size_t(lv.size[size_t(d)]);
        }
        if (singleChannel_)
            lv.texelsR.assign(lv.count * size_t(faces_), 0.0f);
        else if (fi.isFloat)
            lv.texelsF.assign(lv.count * size_t(faces_), glm::vec4(0.0f));
        else
            lv.texels8.assign(lv.count * size_t(faces_), Rgba8{});
        if (desc.format == TexelFormat::I16) lv.texels16.assign(lv.count * size_t(faces_), 0);
        bytes_ += uint64_t(lv.count) * uint64_t(faces_) * uint64_t(fi.bytesPerTexel);
    }
}

Texture::~Texture() {
    if (pool_) pool_->resident -= bytes_;
}

bool Texture::complete() const {
    for (const Level& lv : levels_)
        for (int f = 0; f < faces_; ++f)
            if (!lv.uploaded[size_t(f)]) return false;
    return true;
}

TextureMemory::TextureMemory(const Profile& profile)
    : profile_(&profile), pool_(std::make_shared<Texture::Pool>()) {
    pool_->capacity = profile.textureMemoryBytes;
}
TextureMemory::~TextureMemory() = default;

std::shared_ptr<Texture> TextureMemory::create(const TextureDesc& d) {
    const Profile& p = *profile_;
    // Step 1: the target and format must exist on this machine.
    switch (d.target) {
        case TextureTarget::CubeMap: p.require(Feature::CubeMap); break;
        case TextureTarget::Texture3D: p.require(Feature::Texture3D); break;
        case TextureTarget::Texture4D: p.require(Feature::Texture4D); break;
        default: break;
    }
    const FormatInfo& fi = formatInfo(d.format);
    if (fi.isDepth)
        p.require(Feature::DepthTexture, std::string(fi.name));
    else if (fi.isFloat)
        p.require(Feature::FloatTexture, std::string(fi.name));

    // Step 2: extents. Unused dimensions must be 1; each used one within the limit and,
    // on the power-of-two machines, a power of two.
    const int dims = dimsOf(d.target);
    std::array<int, 4> size{d.width, d.height, d.depth, d.size4};
    int limit = d.target == TextureTarget::CubeMap   ? p.maxCubeMapSize
                : d.target == TextureTarget::Texture4D ? p.max4DTextureSize
                                                       : p.maxTextureSize;
    for (int i = 0; i < 4; ++i) {
        int s = size[size_t(i)];
        if (i >= dims) {
            if (s != 1)
                throw InvalidState(std::string(targetName(d.target)) + " must have extent 1 in dimension " +
                                   std::to_string(i));
            continue;
        }
        if (s < 1) throw InvalidState("texture extent " + std::to_string(s) + " is not positive");
        p.requireLimit(std::string(targetName(d.target)) + " size", s, limit);
        if (p.powerOfTwoOnly && !std::has_single_bit(unsigned(s)))
            p.require(Feature::NonPowerOfTwoTexture,
                      "extent " + std::to_string(s) + " is not a power of two");
    }
    if (d.target == TextureTarget::CubeMap && d.width != d.height)
        throw InvalidState("cube map faces must be square (" + std::to_string(d.width) + "x" +
                           std::to_string(d.height) + ")");
    if (d.levels < 1 || d.levels > fullChainLevels(d))
        throw InvalidState("texture levels " + std::to_string(d.levels) + " outside [1, " +
                           std::to_string(fullChainLevels(d)) + "]");

    // Step 3: reserve the packed size in emulated memory.
    auto t = std::shared_ptr<Texture>(new Texture(d, pool_));
    if (pool_->resident + t->bytes() > pool_->capacity) {
        uint64_t need = pool_->resident + t->bytes();
        t->pool_.reset();  // nothing was reserved
        throw UnsupportedFeature(std::string(p.name), "texture memory",
                                 std::to_string(need) + " bytes exceed the " +
                                     std::to_string(pool_->capacity) + " bytes of the board");
    }
    pool_->resident += t->bytes();
    return t;
}

std::shared_ptr<Texture> TextureMemory::createRenderTarget(const TextureDesc& d) {
    const Profile& p = *profile_;
    p.require(Feature::RenderToTexture, std::string(formatInfo(d.format).name) + " render target");
    switch (d.format) {
        case TexelFormat::RGBA8: break;
        case TexelFormat::R16F: case TexelFormat::RGBA16F:
        case TexelFormat::R32F: case TexelFormat::RGBA32F:
            p.require(Feature::FloatRenderTarget, std::string(formatInfo(d.format).name));
            break;
        case TexelFormat::Depth24: case TexelFormat::Depth32F: break;
        default:
            throw InvalidState(std::string(formatInfo(d.format).name) +
                               " is not a render-target format (RGBA8, R16F, RGBA16F, R32F, "
                               "RGBA32F, Depth24, Depth32F)");
    }
    if (d.target != TextureTarget::Texture1D && d.target != TextureTarget::Texture2D &&
        d.target != TextureTarget::CubeMap)
        throw InvalidState(std::string(targetName(d.target)) + " cannot be a render target");
    auto t = create(d);
    for (auto& lv : t->levels_) lv.uploaded.fill(true);
    t->renderTarget_ = true;
    return t;
}

namespace {

// RGB8 texels to RGBA8 with alpha 255, four per SSSE3 shuffle (x86-64 CPUs without SSSE3
// predate it by years, but they take the scalar loop, which gives the same bytes). Each
// 16-byte load reads 12 bytes of four texels and 4 of the next, so the wide loop stops
// while 16 bytes remain.
__attribute__((target("ssse3"))) void expandRgb8Ssse3(const uint8_t* src, Rgba8* dst,
                                                      size_t count, size_t& done) {
    const __m128i spread = _mm_setr_epi8(0, 1, 2, -1, 3, 4, 5, -1, 6, 7, 8, -1, 9, 10, 11, -1);
    const __m128i alpha = _mm_set1_epi32(int(0xFF000000u));
    size_t i = 0;
    for (; (i + 4) * 3 + 4 <= count * 3; i += 4) {
        const __m128i in = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + 3 * i));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + i),
                         _mm_or_si128(_mm_shuffle_epi8(in, spread), alpha));
    }
    done = i;
}

void expandRgb8(const uint8_t* src, Rgba8* dst, size_t count) {
    static const bool ssse3 = __builtin_cpu_supports("ssse3");
    size_t i = 0;
    if (ssse3) expandRgb8Ssse3(src, dst, count, i);
    for (; i < count; ++i) dst[i] = Rgba8{src[3 * i], src[3 * i + 1], src[3 * i + 2], 255};
}

}  // namespace

void TextureMemory::upload(Texture& t, int level, int face, std::span<const uint8_t> bytes) {
    if (t.pool_ != pool_) throw InvalidState("texture belongs to another texture memory");
    if (level < 0 || level >= t.levels())
        throw InvalidState("upload to level " + std::to_string(level) + " of a texture with " +
                           std::to_string(t.levels()) + " levels");
    if (face < 0 || face >= t.faces())
        throw InvalidState("upload to face " + std::to_string(face) + " of a texture with " +
                           std::to_string(t.faces()) + " faces");
    Texture::Level& lv = t.levels_[size_t(level)];
    const FormatInfo& fi = t.format();
    const size_t expect = lv.count * size_t(fi.bytesPerTexel);
    if (bytes.size() != expect)
        throw InvalidState("upload of " + std::to_string(bytes.size()) + " bytes to a level of " +
                           std::to_string(expect) + " bytes");
    const size_t off = size_t(face) * lv.count;
    // The two formats light fields and environment maps arrive in, without the per-texel
    // format switch of expandTexel8 (a 32·32·128·128 RGB8 light field swapped in every
    // frame spent ~50 ms there): RGBA8 is stored as it comes; RGB8 gains alpha 255
    // (glTexImage2D's RGB: A = 1.0). The same bytes as the general loop.
    if (t.desc().format == TexelFormat::RGBA8) {
        static_assert(sizeof(Rgba8) == 4 && offsetof(Rgba8, r) == 0 && offsetof(Rgba8, a) == 3);
        std::memcpy(lv.texels8.data() + off, bytes.data(), expect);
    } else if (t.desc().format == TexelFormat::RGB8) {
        expandRgb8(bytes.data(), lv.texels8.data() + off, lv.count);
    } else {
        for (size_t i = 0; i < lv.count; ++i) {
            const uint8_t* p = bytes.data() + i * size_t(fi.bytesPerTexel);
            if (t.singleChannel_)
                lv.texelsR[off + i] = expandTexelFloat(t.desc().format, p).x;
            else if (fi.isFloat)
                lv.texelsF[off + i] = expandTexelFloat(t.desc().format, p);
            else
                lv.texels8[off + i] = expandTexel8(t.desc().format, p);
            if (t.is16()) lv.texels16[off + i] = uint16_t(p[0] | (p[1] << 8));
        }
    }
    lv.uploaded[size_t(face)] = true;
    pool_->uploadBytes += expect;
}

void TextureMemory::upload(Texture& t, int level, int face, std::span<const Rgba8> texels) {
    if (t.desc().format != TexelFormat::RGBA8)
        throw InvalidState("Rgba8 texels uploaded to a " + std::string(t.format().name) +
                           " texture; upload its packed bytes instead");
    static_assert(sizeof(Rgba8) == 4);
    upload(t, level, face,
           std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(texels.data()), texels.size() * 4));
}

void TextureMemory::buildBoxMipmaps(Texture& t) {
    const TexelFormat f = t.desc().format;
    if (f != TexelFormat::RGBA8 && f != TexelFormat::RGB8 && f != TexelFormat::L8 &&
        f != TexelFormat::A8 && f != TexelFormat::L8A8 && f != TexelFormat::I8)
        throw InvalidState("buildBoxMipmaps supports the 8-bit byte formats only, not " +
                           std::string(formatInfo(f).name));
    const int bpt = formatInfo(f).bytesPerTexel;
    for (int face = 0; face < t.faces(); ++face) {
        if (!t.levels_[0].uploaded[size_t(face)])
            throw InvalidState("buildBoxMipmaps needs level 0 of face " + std::to_string(face));
        for (int l = 1; l < t.levels(); ++l) {
            const auto& src = t.levels_[size_t(l - 1)];
            const auto& dst = t.levels_[size_t(l)];
            std::vector<uint8_t> packed(dst.count * size_t(bpt));
            // Each destination texel averages the 2 (or 1, where an extent is already 1)
            // source texels per dimension: round(Σ/n) with n a power of two.
            for (size_t i = 0; i < dst.count; ++i) {
                std::array<int, 4> c{};
                size_t r = i;
                for (int d = 0; d < 4; ++d) {
                    c[size_t(d)] = int(r % size_t(dst.size[size_t(d)]));
                    r /= size_t(dst.size[size_t(d)]);
                }
                std::array<uint32_t, 4> sum{};
                uint32_t n = 0;
                for (int k = 0; k < 16; ++k) {
                    std::array<int, 4> sc{};
                    bool skip = false;
                    for (int d = 0; d < 4; ++d) {
                        int bitv = (k >> d) & 1;
                        if (src.size[size_t(d)] == dst.size[size_t(d)] && bitv) skip = true;
                        sc[size_t(d)] = src.size[size_t(d)] == dst.size[size_t(d)]
                                            ? c[size_t(d)]
                                            : 2 * c[size_t(d)] + bitv;
                    }
                    if (skip) continue;
                    Rgba8 v = t.texel8(l - 1, face, sc[0], sc[1], sc[2], sc[3]);
                    sum[0] += v.r; sum[1] += v.g; sum[2] += v.b; sum[3] += v.a;
                    ++n;
                }
                Rgba8 m{uint8_t((sum[0] + n / 2) / n), uint8_t((sum[1] + n / 2) / n),
                        uint8_t((sum[2] + n / 2) / n), uint8_t((sum[3] + n / 2) / n)};
                uint8_t* p = packed.data() + i * size_t(bpt);
                switch (f) {
                    case TexelFormat::RGBA8: p[0] = m.r; p[1] = m.g; p[2] = m.b; p[3] = m.a; break;
                    case TexelFormat::RGB8: p[0] = m.r; p[1] = m.g; p[2] = m.b; break;
                    case TexelFormat::L8: p[0] = m.r; break;
                    case TexelFormat::A8: p[0] = m.a; break;
                    case TexelFormat::L8A8: p[0] = m.r; p[1] = m.a; break;
                    case TexelFormat::I8: p[0] = m.r; break;
                    default: break;
                }
            }
            upload(t, l, face, packed);
        }
    }
}

uint64_t TextureMemory::residentBytes() const { return pool_->resident; }
uint64_t TextureMemory::uploadBytes() const { return pool_->uploadBytes; }
void TextureMemory::resetFrameCounters() { pool_->uploadBytes = 0; }

}  // namespace rg::tex

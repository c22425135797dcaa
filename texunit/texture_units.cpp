// The texture units: state, validation, and the per-quad cascade
// (docs/hardware.md, "Texture stages"; pipeline order of Direct3D 7).
//
// shadeQuad per enabled stage: project the stage's coordinate set (q divide, or cube face
// selection, or none for 4D), one λ for the quad, filter each pixel (tap list on the
// reference path; on the fast path the compiled per-quad kernel of filter_quad.cpp, or
// sampleQuadFast for the other states: same bytes), colour table, then the stage's colour
// and alpha operations (per pixel on the reference path, SSE2 on the whole quad on the
// fast path). The setters recompile the per-stage kernels (refresh), so shadeQuad only
// reads state. const and free of shared mutable state except the fetch counter's
// per-thread shards, so the rasterizer may call it from many threads.
#include "texunit/texture_units.h"

#include "texunit/pixel_texture.h"

#include <string>

#include "core/arith8.h"
#include "core/error.h"
#include "cube_select.h"
#include "fetch_counter.h"
#include "filter_quad.h"
#include "stage_arith.h"
#include "texunit/cube_mapping.h"

namespace rg::tex {

namespace {
constexpr Rgba8 kWhite{255, 255, 255, 255};

void checkStage(int stage) {
    if (stage < 0 || stage >= kMaxStages)
        throw InvalidState("texture stage " + std::to_string(stage) + " outside [0, " +
                           std::to_string(kMaxStages) + ")");
}
void checkSet(int set) {
    if (set < 0 || set >= kMaxTexCoordSets)
        throw InvalidState("texture coordinate set " + std::to_string(set) + " outside [0, " +
                           std::to_string(kMaxTexCoordSets) + ")");
}
bool argIsTexture(uint8_t a) { return (a & arg::SourceMask) == arg::Texture; }

bool opReads(TextureOp op, int which) {  // which: 1, 2 or 0 (Lerp weight)
    switch (op) {
        case TextureOp::Disable:
        case TextureOp::PreModulate: return false;
        case TextureOp::SelectArg1: return which == 1;
        case TextureOp::SelectArg2: return which == 2;
        case TextureOp::Lerp: return true;
        default: return which != 0;
    }
}
}  // namespace

TextureUnits::TextureUnits() : fetches_(std::make_shared<detail::FetchCounter>()) { refresh(); }

void TextureUnits::setStage(int i, const StageState& s) {
    checkStage(i);
    if (s.colorOp >= TextureOp::Count || s.alphaOp >= TextureOp::Count)
        throw InvalidState("texture op out of range at stage " + std::to_string(i));
    // Refused here rather than at draw time, so that no state the device holds (and a
    // trace records) has an ALPHAOP without a meaning (docs/hardware.md, "Texture stages").
    if (colourOnlyOp(s.alphaOp))
        throw InvalidState("stage " + std::to_string(i) + ": D3DTOP_" + std::string(textureOpName(s.alphaOp)) +
                           " is a colour-only op");
    if (s.texCoordIndex >= kMaxTexCoordSets)
        throw InvalidState("stage " + std::to_string(i) + ": texture coordinate index " +
                           std::to_string(s.texCoordIndex) + " outside [0, " +
                           std::to_string(kMaxTexCoordSets) + ")");
    if (s.colorScaleShift > 2 || s.alphaScaleShift > 2)
        throw InvalidState("stage " + std::to_string(i) + ": scale shift above 2 (scale 4)");
    for (uint8_t a : {s.colorArg0, s.colorArg1, s.colorArg2, s.alphaArg0, s.alphaArg1, s.alphaArg2})
        if ((a & arg::SourceMask) > arg::Specular ||
            (a & ~(arg::SourceMask | arg::Complement | arg::AlphaReplicate)) != 0)
            throw InvalidState("stage " + std::to_string(i) + ": texture argument 0x" +
                               std::to_string(int(a)) + " is not a D3DTA_ value");
    units_[size_t(i)].stage = s;
    refresh();
}
const StageState& TextureUnits::stage(int i) const {
    checkStage(i);
    return units_[size_t(i)].stage;
}
void TextureUnits::setTexture(int i, std::shared_ptr<const Texture> t) {
    checkStage(i);
    units_[size_t(i)].texture = std::move(t);
    refresh();
}
const std::shared_ptr<const Texture>& TextureUnits::texture(int i) const {
    checkStage(i);
    return units_[size_t(i)].texture;
}
void TextureUnits::setSampler(int i, const SamplerState& s) {
    checkStage(i);
    units_[size_t(i)].sampler = s;
    refresh();
}
const SamplerState& TextureUnits::sampler(int i) const {
    checkStage(i);
    return units_[size_t(i)].sampler;
}
void TextureUnits::setColorTable(int i, std::shared_ptr<const ColorTable> t) {
    checkStage(i);
    units_[size_t(i)].colorTable = std::move(t);
    refresh();
}
void TextureUnits::setTextureFactor(Rgba8 f) { tfactor_ = f; }
void TextureUnits::setTexGen(int set, const TexGenState& g) {
    checkSet(set);
    texGen_[size_t(set)] = g;
    refresh();
}
const TexGenState& TextureUnits::texGen(int set) const {
    checkSet(set);
    return texGen_[size_t(set)];
}
void TextureUnits::setPixelTexture(const PixelTextureState& s) {
    checkStage(s.stage);
    pixelTexture_ = s;
    pixelLut_ = compilePixelTransfer();
}
void TextureUnits::setTextureMemory(std::shared_ptr<TextureMemory> m) { memory_ = std::move(m); }

TextureCounters TextureUnits::counters() const {
    TextureCounters c;
    c.texelFetches = fetches_->total();
    c.uploadBytes = memory_ ? memory_->uploadBytes() : 0;
    return c;
}
void TextureUnits::resetCounters() {
    fetches_->reset();
    if (memory_) memory_->resetFrameCounters();
}

int TextureUnits::activeStages() const {
    int n = 0;
    while (n < kMaxStages && units_[size_t(n)].stage.colorOp != TextureOp::Disable) ++n;
    return n;
}

bool TextureUnits::readsTexture(int i) const {
    const StageState& s = units_[size_t(i)].stage;
    if (!units_[size_t(i)].texture) return false;
    if (s.colorOp == TextureOp::PreModulate || s.colorOp == TextureOp::BlendTextureAlpha ||
        s.colorOp == TextureOp::BlendTextureAlphaPM || s.alphaOp == TextureOp::BlendTextureAlpha ||
        s.alphaOp == TextureOp::BlendTextureAlphaPM)
        return true;
    // A stage's texture also feeds the next stage when this one premodulates.
    if (i > 0 && units_[size_t(i - 1)].stage.colorOp == TextureOp::PreModulate) return true;
    return (opReads(s.colorOp, 1) && argIsTexture(s.colorArg1)) ||
           (opReads(s.colorOp, 2) && argIsTexture(s.colorArg2)) ||
           (opReads(s.colorOp, 0) && argIsTexture(s.colorArg0)) ||
           (opReads(s.alphaOp, 1) && argIsTexture(s.alphaArg1)) ||
           (opReads(s.alphaOp, 2) && argIsTexture(s.alphaArg2)) ||
           (opReads(s.alphaOp, 0) && argIsTexture(s.alphaArg0));
}

void TextureUnits::refresh() {
    static_assert(kMaxStages <= int(std::tuple_size_v<decltype(detail::CompiledStages::stage)>));
    active_ = activeStages();
    sampling_ = 0;
    auto compiled = std::make_shared<detail::CompiledStages>();
    for (int i = 0; i < active_; ++i) {
        compiled->stageKernel[size_t(i)] = uint8_t(detail::quad::stageKernel(units_[size_t(i)].stage));
        if (!readsTexture(i)) continue;
        sampling_ |= 1u << i;
        const Unit& u = units_[size_t(i)];
        compiled->stage[size_t(i)] =
            detail::compileQuadSampler(*u.texture, u.sampler, texGen_[u.stage.texCoordIndex].projected,
                                       u.colorTable != nullptr);
        if (i > 0 && (sampling_ & (1u << (i - 1))) &&
            units_[size_t(i - 1)].stage.texCoordIndex == u.stage.texCoordIndex &&
            detail::sameFootprint(compiled->stage[size_t(i - 1)], compiled->stage[size_t(i)]))
            compiled->sharesFootprint |= 1u << i;
    }
    for (int i = 0; i < active_; ++i) compiled->state[size_t(i)] = units_[size_t(i)].stage;
    detail::compileCascade(*compiled, active_, sampling_);
    compiled_ = std::move(compiled);
    pixelLut_ = compilePixelTransfer();
}

bool TextureUnits::passThrough() const { return active_ == 0; }

uint32_t TextureUnits::texCoordSetsUsed() const {
    uint32_t m = 0;
    const int n = activeStages();
    for (int i = 0; i < n; ++i)
        if (readsTexture(i)) m |= 1u << units_[size_t(i)].stage.texCoordIndex;
    return m;
}

glm::vec4 TextureUnits::processVertexTexCoord(int set, const VertexEye& v, const glm::vec4& in) const {
    if (set < 0 || set >= kMaxTexCoordSets) return in;
    return generateTexCoord(texGen_[size_t(set)], v, in);
}

void TextureUnits::validate(const Profile& p) const {
    const int n = activeStages();
    if (n > 0) {
        if (p.api == Api::OpenGL12) {
            // One texture unit on the SGI machines; the ops must be what GL's
            // environments and ARB_texture_env_combine can say.
            for (int i = 0; i < n; ++i) {
                const StageState& s = units_[size_t(i)].stage;
                for (TextureOp op : {s.colorOp, s.alphaOp}) {
                    switch (op) {
                        case TextureOp::Disable:
                        case TextureOp::SelectArg1:
                        case TextureOp::SelectArg2:
                        case TextureOp::Modulate:
                        case TextureOp::Add:
                        case TextureOp::BlendTextureAlpha:
                        case TextureOp::Lerp: break;
                        case TextureOp::AddSigned:
                        case TextureOp::Subtract:
                            p.require(Feature::TextureEnvCombine, std::string(textureOpName(op)));
                            break;
                        default:
                            p.require(Feature::TextureStages,
                                      "D3DTOP_" + std::string(textureOpName(op)) +
                                          " has no OpenGL texture environment");
                    }
                }
                if (s.colorScaleShift || s.alphaScaleShift)
                    p.require(Feature::TextureEnvCombine, "RGB_SCALE/ALPHA_SCALE");
            }
        } else {
            p.require(Feature::TextureStages);
            for (int i = 0; i < n; ++i) {
                const StageState& s = units_[size_t(i)].stage;
                if ((s.colorOp == TextureOp::Lerp || s.alphaOp == TextureOp::Lerp) &&
                    p.api == Api::Direct3D7)
                    throw UnsupportedFeature(std::string(p.name), "D3DTOP_LERP",
                                             "a Direct3D 8 operation");
                if ((s.colorScaleShift || s.alphaScaleShift) && p.api == Api::Direct3D7)
                    throw UnsupportedFeature(std::string(p.name), "stage output scale",
                                             "use MODULATE2X/4X");
            }
        }
        p.requireLimit("texture stages", n, p.maxTextureStages);
    }
    for (int i = 0; i < n; ++i) {
        const Unit& u = units_[size_t(i)];
        const StageState& s = u.stage;
        if (s.texCoordIndex >= p.maxTexCoordSets || s.texCoordIndex >= kMaxTexCoordSets)
            throw UnsupportedFeature(std::string(p.name), "texture coordinate set " +
                                                              std::to_string(s.texCoordIndex));
        if (u.texture && readsTexture(i)) {
            const Texture& t = *u.texture;
            if (!t.complete())
                throw InvalidState("stage " + std::to_string(i) +
                                   ": texture incomplete (a level or face was never uploaded)");
            switch (t.desc().target) {
                case TextureTarget::CubeMap: p.require(Feature::CubeMap); break;
                case TextureTarget::Texture4D: p.require(Feature::Texture4D); break;
                case TextureTarget::Texture3D: p.require(Feature::Texture3D); break;
                default: break;
            }
            if (t.isFloat()) p.require(Feature::FloatTexture);
            if (texGen_[s.texCoordIndex].projected &&
                t.desc().target != TextureTarget::CubeMap && t.desc().target != TextureTarget::Texture4D)
                p.require(Feature::ProjectedTexture);
        }
        if (u.colorTable) {
            p.require(Feature::TextureColorTable);
            p.requireLimit("texture colour table size", int64_t(u.colorTable->entries.size()),
                           p.colorTableSize);
        }
    }
    // Coordinate generation of the sets the stages read: Direct3D has only its TCI modes
    // (OBJECT_LINEAR, EYE_LINEAR and SPHERE_MAP are glTexGen's).
    if (p.api != Api::OpenGL12) {
        const uint32_t used = texCoordSetsUsed();
        for (int set = 0; set < kMaxTexCoordSets; ++set) {
            if (!(used & (1u << set))) continue;
            const TexGenMode m = texGen_[size_t(set)].mode;
            if (m == TexGenMode::ObjectLinear || m == TexGenMode::EyeLinear || m == TexGenMode::SphereMap)
                throw UnsupportedFeature(std::string(p.name), "OpenGL texture-coordinate generation",
                                         "set " + std::to_string(set) + " uses a glTexGen mode; "
                                         "Direct3D offers D3DTSS_TCI_* and the texture matrix");
        }
    }
    validatePixelTexture(p);
}

void TextureUnits::validatePixelTexture(const Profile& p) const {
    if (pixelTexture_.enabled) {
        p.require(Feature::PixelTexture, "a pixel transfer with pixel texture enabled");
        checkStage(pixelTexture_.stage);
        const Unit& u = units_[pixelTexture_.stage];
        if (!u.texture) throw InvalidState("pixel texture enabled without a texture");
        if (!u.texture->complete()) throw InvalidState("pixel texture: texture incomplete");
        if (u.texture->desc().target == TextureTarget::Texture4D) p.require(Feature::Texture4D);
        if (u.texture->desc().target == TextureTarget::CubeMap)
            throw InvalidState("pixel texture takes 1D, 2D, 3D or 4D textures, not cube maps");
        if (u.colorTable) {
            p.require(Feature::TextureColorTable);
            p.requireLimit("texture colour table size", int64_t(u.colorTable->entries.size()),
                           p.colorTableSize);
        }
    }
}

void TextureUnits::projectQuad(int i, const FragmentQuad& quad, std::array<glm::vec4, 4>& c,
                               int32_t& lambda) const {
    const Unit& u = units_[size_t(i)];
    const Texture& t = *u.texture;
    const auto& in = quad.texCoord[u.stage.texCoordIndex];
    const int base = std::clamp(u.sampler.baseLevel, 0, t.levels() - 1);
    switch (t.desc().target) {
        case TextureTarget::CubeMap: {
            // λ from all four pixels measured on pixel 0's face; then each pixel's own face.
            std::array<glm::vec4, 4> onFace;
            CubeFace f0 = CubeFace::PositiveX;
            for (int p = 0; p < 4; ++p) {
                const glm::vec3 r(in[size_t(p)]);
                const CubeCoord own = detail::selectCubeFace(r);
                if (p == 0) f0 = own.face;
                c[size_t(p)] = glm::vec4(own.s, own.t, float(int(own.face)), 0.0f);
                // Same face as pixel 0: the same row of the table, the same numbers.
                const CubeCoord cc = own.face == f0 ? own : detail::projectOntoCubeFace(f0, r);
                onFace[size_t(p)] = glm::vec4(cc.s, cc.t, 0.0f, 0.0f);
            }
            lambda = quadLambda(onFace, t.levelSize(base), 2);
            break;
        }
        case TextureTarget::Texture4D:
            // SGIS_texture4D: q is the fourth coordinate, never a divisor.
            for (int p = 0; p < 4; ++p) c[size_t(p)] = in[size_t(p)];
            lambda = quadLambda(c, t.levelSize(base), 4);
            break;
        default:
            // The projective divide when the set is projected (GL: always; D3D7:
            // D3DTTFF_PROJECTED with the divisor placed in q by the texture matrix).
            if (texGen_[u.stage.texCoordIndex].projected) {
                for (int p = 0; p < 4; ++p) {
                    const glm::vec4& v = in[size_t(p)];
                    c[size_t(p)] = glm::vec4(v.x / v.w, v.y / v.w, v.z / v.w, 0.0f);
                }
            } else {
                for (int p = 0; p < 4; ++p) c[size_t(p)] = glm::vec4(glm::vec3(in[size_t(p)]), 0.0f);
            }
            lambda = quadLambda(c, t.levelSize(base), t.dims());
            break;
    }
    lambda = biasAndClampLambda(lambda, u.sampler);
}

TapList TextureUnits::queryTaps(int stage, const FragmentQuad& quad, int pixel) const {
    checkStage(stage);
    TapList taps;
    const Unit& u = units_[size_t(stage)];
    if (!u.texture || pixel < 0 || pixel > 3) return taps;
    std::array<glm::vec4, 4> c;
    int32_t lambda;
    projectQuad(stage, quad, c, lambda);
    gatherTaps(*u.texture, u.sampler, c[size_t(pixel)], lambda, taps);
    return taps;
}

std::array<Rgba8, 4> TextureUnits::sampleStage(int stage, const FragmentQuad& quad, Path path) const {
    checkStage(stage);
    std::array<Rgba8, 4> out{kWhite, kWhite, kWhite, kWhite};
    const Unit& u = units_[size_t(stage)];
    if (!u.texture) return out;
    std::array<glm::vec4, 4> c;
    int32_t lambda;
    projectQuad(stage, quad, c, lambda);
    uint64_t fetched = 0;
    if (u.colorTable && u.texture->is16()) {
        // The 16-bit index path (docs/hardware.md, "Colour tables"): the filtered 16-bit
        // intensity indexes the table; one path for both, the tap list.
        for (int p = 0; p < 4; ++p) {
            TapList taps;
            gatherTaps(*u.texture, u.sampler, c[size_t(p)], lambda, taps);
            out[size_t(p)] = applyColorTable16(*u.colorTable, resolveTaps16(*u.texture, u.sampler, taps));
            fetched += uint64_t(taps.count);
        }
        fetches_->add(fetched);
        return out;
    }
    if (path == Path::Reference) {
        for (int p = 0; p < 4; ++p) {
            TapList taps;
            gatherTaps(*u.texture, u.sampler, c[size_t(p)], lambda, taps);
            out[size_t(p)] = resolveTaps(*u.texture, u.sampler, taps);
            fetched += uint64_t(taps.count);
        }
    } else {
        // The level choice once per quad; counts what the reference would fetch.
        fetched = sampleQuadFast(*u.texture, u.sampler, c, lambda, out);
    }
    if (u.colorTable)
        for (auto& o : out) o = applyColorTable(*u.colorTable, o);
    fetches_->add(fetched);
    return out;
}

bool TextureUnits::shadesPairs() const { return compiled_->cascadePair != nullptr; }

uint64_t TextureUnits::shadeQuadPair(const FragmentQuadPair& pair, std::array<Rgba8, 8>& out) const {
    return pairShader()(pair, out);
}
TextureUnits::PairShader TextureUnits::pairShader() const {
    return {compiled_->cascadePair, compiled_.get(), detail::quad::splat(tfactor_)};
}
void TextureUnits::addFetches(uint64_t n) const {
    if (n) fetches_->add(n);
}

void TextureUnits::shadeQuad(const FragmentQuad& quad, std::array<Rgba8, 4>& out, Path path) const {
    const int n = active_;
    if (path == Path::Fast) {
        // The same cascade on SSE2 registers of four pixels (stage_arith.h, quad::), with
        // the compiled samplers where the state has one; fetches added once per quad.
        namespace q = detail::quad;
        const detail::CompiledStages& compiled = *compiled_;
        if (compiled.cascade) {
            __m128i o;
            fetches_->add(compiled.cascade(compiled, quad, q::splat(tfactor_), o));
            q::store(out, o);
            return;
        }
        q::Regs r;
        r[arg::Diffuse] = q::loadPixels(quad.diffuse);
        r[arg::Specular] = q::loadPixels(quad.specular);
        r[arg::Current] = r[arg::Diffuse];
        r[arg::TFactor] = q::splat(tfactor_);
        __m128i premod = q::ones();
        bool havePremod = false;
        uint64_t fetched = 0;
        detail::QuadFootprint footprint;  // kept for the next stage when it shares it
        for (int i = 0; i < n; ++i) {
            const StageState& st = units_[size_t(i)].stage;
            r[arg::Texture] = q::ones();
            if (sampling_ & (1u << i)) {
                const detail::QuadSampler& qs = compiled.stage[size_t(i)];
                if (compiled.sharesFootprint & (1u << i)) {
                    r[arg::Texture] = qs.gather(qs, footprint);  // stage i − 1's footprint
                    fetched += footprint.fetches;
                } else if (compiled.sharesFootprint & (2u << i)) {
                    fetched += qs.prepare(qs, quad.texCoord[st.texCoordIndex], footprint);
                    r[arg::Texture] = qs.gather(qs, footprint);
                } else if (qs.fn) {
                    fetched += qs.fn(qs, quad.texCoord[st.texCoordIndex], r[arg::Texture]);
                } else {
                    r[arg::Texture] = q::load(sampleStage(i, quad, path));
                }
            }
            if (havePremod) {
                r[arg::Texture] = q::mulDiv255(r[arg::Texture], premod);
                havePremod = false;
            }
            if (st.colorOp == TextureOp::PreModulate) {
                premod = r[arg::Texture];
                havePremod = true;
            }
            const auto kernel = q::StageKernel(compiled.stageKernel[size_t(i)]);
            if (kernel != q::StageKernel::Scalar) {
                r[arg::Current] = q::evaluateKernel(kernel, st, r);
            } else {
                std::array<Rgba8, 4> diffuse, specular, current, texel, next;
                q::store(current, r[arg::Current]);
                q::store(texel, r[arg::Texture]);
                std::array<StageInputs, 4> in;
                for (int p = 0; p < 4; ++p)
                    in[size_t(p)] = {quad.diffuse[size_t(p)], quad.specular[size_t(p)],
                                     current[size_t(p)], texel[size_t(p)], tfactor_};
                detail::evaluateStageQuad(st, in, next);
                r[arg::Current] = q::load(next);
            }
        }
        if (fetched) fetches_->add(fetched);
        q::store(out, r[arg::Current]);
        return;
    }

    // The reference: the docs' per-pixel definition, one pixel at a time.
    std::array<Rgba8, 4> current = quad.diffuse;
    std::array<Rgba8, 4> premod{};
    bool havePremod = false;
    for (int i = 0; i < n; ++i) {
        const StageState& st = units_[size_t(i)].stage;
        std::array<Rgba8, 4> texel{kWhite, kWhite, kWhite, kWhite};
        if (sampling_ & (1u << i)) texel = sampleStage(i, quad, path);
        if (havePremod) {
            // D3DTOP_PREMODULATE of the previous stage: its texture multiplies this one's.
            for (int p = 0; p < 4; ++p) {
                Rgba8& t = texel[size_t(p)];
                const Rgba8& m = premod[size_t(p)];
                t = {uint8_t(arith8::mulDiv255(t.r, m.r)), uint8_t(arith8::mulDiv255(t.g, m.g)),
                     uint8_t(arith8::mulDiv255(t.b, m.b)), uint8_t(arith8::mulDiv255(t.a, m.a))};
            }
            havePremod = false;
        }
        if (st.colorOp == TextureOp::PreModulate) {
            premod = texel;
            havePremod = true;
        }
        for (int p = 0; p < 4; ++p)
            current[size_t(p)] = detail::evaluateStage(
                st, {quad.diffuse[size_t(p)], quad.specular[size_t(p)], current[size_t(p)],
                     texel[size_t(p)], tfactor_});
    }
    out = current;
}

}  // namespace rg::tex

// The Mesa peer: trace records → OpenGL 1.3 fixed function on OSMesa (llvmpipe).
//
// What maps how (D3D7 → GL):
//   rows                      our row r is GL window row r (OSMESA_Y_UP = 1: buffer row 0 is
//                              GL's row 0), so every rectangle (viewport, scissor, clears,
//                              pixel transfers, read-backs) passes unchanged. Not only
//                              convenient: llvmpipe breaks fill-rule ties by GL's rule with
//                              y up, which in these rows is Direct3D's top-left rule, ours
//                              (drawn the other way up, every horizontal edge through pixel
//                              centres went to the other triangle: 2.3% of raster-fill-rule)
//   untransformed vertices    MODELVIEW = view·world, PROJECTION = P with clip y negated
//                              (the image is upside down in GL's terms, right way up in
//                              ours); glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) keeps
//                              Direct3D's clip z ∈ [0, w] and window z = minZ + z·(maxZ − minZ)
//   pre-transformed vertices  (x, y, z, 1)/rhw through a power-of-two viewport and ortho
//                              matrix (every step a power of two: window positions exact),
//                              z unchanged, 1/w interpolated, both sampling pixel centres at
//                              x + ½; scissored to viewport ∩ scissor as ours
//   cull                      the negated y mirrors GL's winding: D3DCULL_CW culls GL_FRONT
//                              with GL_CCW front
//   clear                     scissored to viewport ∩ scissor, colour unmasked
//   blend factors and ops     glBlendFunc / glBlendEquation; BOTHSRCALPHA as
//                              (SRC_ALPHA, ONE_MINUS_SRC_ALPHA), BOTHINVSRCALPHA swapped
//   stages                    GL_COMBINE (ARB_texture_env_combine, _dot3, crossbar)
//   specular add              GL_COLOR_SUM with the secondary colour
//   texgen                    TCI modes as REFLECTION_MAP, NORMAL_MAP, EYE_LINEAR
//   drawPixels / copyPixels   glWindowPos at (x, y), rows going up in GL = down in ours;
//                              texturing, blending and tests off (ours writes the colour
//                              buffer directly)
//   initial contents          glDrawPixels of the Framebuffer record's colour and depth, or
//                              a clear to zero
#include "conformance/mesa_player.h"
#include "core/fd_io.h"
#include "mesa_program_player.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "core/error.h"

namespace rg::conformance {

using namespace rg::raster;
namespace fs = std::filesystem;

namespace {

bool glOpExpressible(tex::TextureOp op) {
    using tex::TextureOp;
    switch (op) {
        case TextureOp::Disable: case TextureOp::SelectArg1: case TextureOp::SelectArg2:
        case TextureOp::Modulate: case TextureOp::Modulate2x: case TextureOp::Modulate4x:
        case TextureOp::Add: case TextureOp::AddSigned: case TextureOp::AddSigned2x:
        case TextureOp::Subtract: case TextureOp::BlendDiffuseAlpha: case TextureOp::BlendTextureAlpha:
        case TextureOp::BlendFactorAlpha: case TextureOp::BlendCurrentAlpha: case TextureOp::DotProduct3:
        case TextureOp::Lerp:
            return true;
        default: return false;
    }
}

GLenum compare(CompareFunc f) { return GL_NEVER + GLenum(f); }  // same order as GL

GLenum blendFactor(BlendFactor f, bool dst) {
    switch (f) {
        case BlendFactor::Zero: return GL_ZERO;
        case BlendFactor::One: return GL_ONE;
        case BlendFactor::SrcColor: return GL_SRC_COLOR;
        case BlendFactor::InvSrcColor: return GL_ONE_MINUS_SRC_COLOR;
        case BlendFactor::SrcAlpha: return GL_SRC_ALPHA;
        case BlendFactor::InvSrcAlpha: return GL_ONE_MINUS_SRC_ALPHA;
        case BlendFactor::DestAlpha: return GL_DST_ALPHA;
        case BlendFactor::InvDestAlpha: return GL_ONE_MINUS_DST_ALPHA;
        case BlendFactor::DestColor: return GL_DST_COLOR;
        case BlendFactor::InvDestColor: return GL_ONE_MINUS_DST_COLOR;
        case BlendFactor::SrcAlphaSat: return GL_SRC_ALPHA_SATURATE;
        case BlendFactor::BothSrcAlpha: return GL_SRC_ALPHA;
        case BlendFactor::BothInvSrcAlpha: return GL_ONE_MINUS_SRC_ALPHA;
    }
    return dst ? GL_ZERO : GL_ONE;
}

GLenum blendEquation(BlendOp op) {
    switch (op) {
        case BlendOp::Add: return GL_FUNC_ADD;
        case BlendOp::Subtract: return GL_FUNC_SUBTRACT;
        case BlendOp::RevSubtract: return GL_FUNC_REVERSE_SUBTRACT;
        case BlendOp::Min: return GL_MIN;
        case BlendOp::Max: return GL_MAX;
    }
    return GL_FUNC_ADD;
}

GLenum wrap(tex::AddressMode a) {
    switch (a) {
        case tex::AddressMode::Wrap: return GL_REPEAT;
        case tex::AddressMode::Mirror: return GL_MIRRORED_REPEAT;
        case tex::AddressMode::Clamp: return GL_CLAMP;
        case tex::AddressMode::ClampToEdge: return GL_CLAMP_TO_EDGE;
        case tex::AddressMode::Border: return GL_CLAMP_TO_BORDER;
    }
    return GL_REPEAT;
}

GLenum internalFormat(tex::BaseFormat b) {
    switch (b) {
        case tex::BaseFormat::Alpha: return GL_ALPHA8;
        case tex::BaseFormat::Luminance: return GL_LUMINANCE8;
        case tex::BaseFormat::LuminanceAlpha: return GL_LUMINANCE8_ALPHA8;
        case tex::BaseFormat::Intensity: return GL_INTENSITY8;
        case tex::BaseFormat::Rgb: return GL_RGB8;
        case tex::BaseFormat::Rgba: return GL_RGBA8;
    }
    return GL_RGBA8;
}

GLenum targetOf(tex::TextureTarget t) {
    switch (t) {
        case tex::TextureTarget::Texture1D: return GL_TEXTURE_1D;
        case tex::TextureTarget::Texture2D: return GL_TEXTURE_2D;
        case tex::TextureTarget::Texture3D: return GL_TEXTURE_3D;
        case tex::TextureTarget::CubeMap: return GL_TEXTURE_CUBE_MAP;
        default: return 0;
    }
}

// One D3D argument as a combine (source, operand); `alpha`: for the alpha channel.
void combineArg(uint8_t a, bool alpha, GLenum& source, GLenum& operand) {
    switch (a & tex::arg::SourceMask) {
        case tex::arg::Diffuse: source = GL_PRIMARY_COLOR; break;
        case tex::arg::Current: source = GL_PREVIOUS; break;
        case tex::arg::Texture: source = GL_TEXTURE; break;
        default: source = GL_CONSTANT; break;  // TFACTOR
    }
    const bool comp = a & tex::arg::Complement;
    if (alpha || (a & tex::arg::AlphaReplicate))
        operand = comp ? GL_ONE_MINUS_SRC_ALPHA : GL_SRC_ALPHA;
    else
        operand = comp ? GL_ONE_MINUS_SRC_COLOR : GL_SRC_COLOR;
}

void combineChannel(tex::TextureOp op, uint8_t a1, uint8_t a2, uint8_t a0, int shift, bool alpha) {
    using tex::TextureOp;
    const GLenum combine = alpha ? GL_COMBINE_ALPHA : GL_COMBINE_RGB;
    const GLenum src[3] = {GLenum(alpha ? GL_SOURCE0_ALPHA : GL_SOURCE0_RGB), GLenum(alpha ? GL_SOURCE1_ALPHA : GL_SOURCE1_RGB),
                           GLenum(alpha ? GL_SOURCE2_ALPHA : GL_SOURCE2_RGB)};
    const GLenum opd[3] = {GLenum(alpha ? GL_OPERAND0_ALPHA : GL_OPERAND0_RGB), GLenum(alpha ? GL_OPERAND1_ALPHA : GL_OPERAND1_RGB),
                           GLenum(alpha ? GL_OPERAND2_ALPHA : GL_OPERAND2_RGB)};
    auto set = [&](int i, uint8_t a) {
        GLenum s, o;
        combineArg(a, alpha, s, o);
        glTexEnvi(GL_TEXTURE_ENV, src[i], GLint(s));
        glTexEnvi(GL_TEXTURE_ENV, opd[i], GLint(o));
    };
    auto weight = [&](GLenum source) {
        glTexEnvi(GL_TEXTURE_ENV, src[2], GLint(source));
        glTexEnvi(GL_TEXTURE_ENV, opd[2], GL_SRC_ALPHA);
    };
    GLenum func = GL_MODULATE;
    switch (op) {
        case TextureOp::SelectArg1: func = GL_REPLACE; set(0, a1); break;
        case TextureOp::SelectArg2: func = GL_REPLACE; set(0, a2); break;
        case TextureOp::Modulate: case TextureOp::Modulate2x: case TextureOp::Modulate4x:
            func = GL_MODULATE; set(0, a1); set(1, a2);
            shift += op == TextureOp::Modulate2x ? 1 : op == TextureOp::Modulate4x ? 2 : 0;
            break;
        case TextureOp::Add: func = GL_ADD; set(0, a1); set(1, a2); break;
        case TextureOp::AddSigned: case TextureOp::AddSigned2x:
            func = GL_ADD_SIGNED; set(0, a1); set(1, a2);
            shift += op == TextureOp::AddSigned2x ? 1 : 0;
            break;
        case TextureOp::Subtract: func = GL_SUBTRACT; set(0, a1); set(1, a2); break;
        case TextureOp::BlendDiffuseAlpha: func = GL_INTERPOLATE; set(0, a1); set(1, a2); weight(GL_PRIMARY_COLOR); break;
        case TextureOp::BlendTextureAlpha: func = GL_INTERPOLATE; set(0, a1); set(1, a2); weight(GL_TEXTURE); break;
        case TextureOp::BlendFactorAlpha: func = GL_INTERPOLATE; set(0, a1); set(1, a2); weight(GL_CONSTANT); break;
        case TextureOp::BlendCurrentAlpha: func = GL_INTERPOLATE; set(0, a1); set(1, a2); weight(GL_PREVIOUS); break;
        case TextureOp::Lerp: func = GL_INTERPOLATE; set(0, a1); set(1, a2); set(2, a0); break;
        case TextureOp::DotProduct3: func = alpha ? GL_REPLACE : GL_DOT3_RGBA; set(0, a1); set(1, a2); break;
        default: break;
    }
    glTexEnvi(GL_TEXTURE_ENV, combine, GLint(func));
    glTexEnvf(GL_TEXTURE_ENV, alpha ? GL_ALPHA_SCALE : GL_RGB_SCALE, float(1 << std::min(shift, 2)));
}

// ---- the player (runs in the child) ------------------------------------------------
struct GlPlayer {
    explicit GlPlayer(const Trace& t) : trace(t), w(t.width), h(t.height) {}
    const Trace& trace;
    int w, h;
    PipelineState state;
    Viewport viewport;
    Rect scissor;
    glm::mat4 world{1}, view{1}, projection{1};
    std::array<tex::StageState, tex::kMaxStages> stages{};
    std::array<tex::SamplerState, tex::kMaxStages> samplers{};
    std::array<uint64_t, tex::kMaxStages> bound{};
    std::array<tex::TexGenState, tex::kMaxTexCoordSets> texGens{};
    Rgba8 tfactor{255, 255, 255, 255};
    std::map<uint64_t, GLuint> names;
    std::vector<uint8_t> readBack;
    int units = 1;

    GLuint textureName(uint64_t id) {
        if (auto it = names.find(id); it != names.end()) return it->second;
        const TraceTexture& t = trace.textures.at(id);
        GLuint name;
        glGenTextures(1, &name);
        const GLenum target = targetOf(t.desc.target);
        glBindTexture(target, name);
        const int faces = t.desc.target == tex::TextureTarget::CubeMap ? 6 : 1;
        const tex::FormatInfo& fi = tex::formatInfo(t.desc.format);
        for (int l = 0; l < t.desc.levels; ++l)
            for (int f = 0; f < faces; ++f) {
                const std::vector<uint8_t>& packed = t.levelFaces[size_t(l * faces + f)];
                std::vector<Rgba8> rgba(packed.size() / size_t(fi.bytesPerTexel));
                for (size_t i = 0; i < rgba.size(); ++i)
                    rgba[i] = tex::expandTexel8(t.desc.format, packed.data() + i * size_t(fi.bytesPerTexel));
                const int lw = std::max(1, t.desc.width >> l), lh = std::max(1, t.desc.height >> l),
                          ld = std::max(1, t.desc.depth >> l);
                const GLenum ifmt = internalFormat(fi.base);
                if (target == GL_TEXTURE_1D)
                    glTexImage1D(target, l, GLint(ifmt), lw, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
                else if (target == GL_TEXTURE_3D)
                    glTexImage3D(target, l, GLint(ifmt), lw, lh, ld, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
                else
                    glTexImage2D(target == GL_TEXTURE_CUBE_MAP ? GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f) : target, l,
                                 GLint(ifmt), lw, lh, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
            }
        names.emplace(id, name);
        return name;
    }

    int activeStages() const {
        int n = 0;
        while (n < tex::kMaxStages && stages[size_t(n)].colorOp != tex::TextureOp::Disable) ++n;
        return n;
    }

    void applyFragmentState() {
        const PipelineState& s = state;
        s.depthTest ? glEnable(GL_DEPTH_TEST) : glDisable(GL_DEPTH_TEST);
        glDepthFunc(compare(s.depthFunc));
        glDepthMask(s.depthWrite ? GL_TRUE : GL_FALSE);
        s.alphaTest ? glEnable(GL_ALPHA_TEST) : glDisable(GL_ALPHA_TEST);
        glAlphaFunc(compare(s.alphaFunc), float(s.alphaRef) / 255.0f);
        s.blend ? glEnable(GL_BLEND) : glDisable(GL_BLEND);
        GLenum src = blendFactor(s.srcBlend, false), dst = blendFactor(s.dstBlend, true);
        if (s.srcBlend == BlendFactor::BothSrcAlpha) dst = GL_ONE_MINUS_SRC_ALPHA;
        if (s.srcBlend == BlendFactor::BothInvSrcAlpha) dst = GL_SRC_ALPHA;
        glBlendFunc(src, dst);
        glBlendEquation(blendEquation(s.blendOp));
        glColorMask(s.colorWriteMask & kWriteR, s.colorWriteMask & kWriteG, s.colorWriteMask & kWriteB,
                    s.colorWriteMask & kWriteA);
        s.scissorTest ? glEnable(GL_SCISSOR_TEST) : glDisable(GL_SCISSOR_TEST);
        glScissor(scissor.x, scissor.y, scissor.width, scissor.height);
        glShadeModel(s.shade == ShadeMode::Flat ? GL_FLAT : GL_SMOOTH);
        // Direct3D's provoking vertex is the first of a list/strip triangle and the second
        // of a fan triangle: GL's first-vertex convention (ARB_provoking_vertex) exactly.
        glProvokingVertex(GL_FIRST_VERTEX_CONVENTION);
        s.specularEnable ? glEnable(GL_COLOR_SUM) : glDisable(GL_COLOR_SUM);
        // Direct3D culls by the winding seen on screen with y down. GL's window rows are
        // ours here, but its y points up, so a triangle clockwise on our screen is
        // counter-clockwise to GL: D3DCULL_CW culls GL's front faces when GL_CCW is front.
        if (s.cull == CullMode::None) {
            glDisable(GL_CULL_FACE);
        } else {
            glEnable(GL_CULL_FACE);
            glFrontFace(GL_CCW);
            glCullFace(s.cull == CullMode::CW ? GL_FRONT : GL_BACK);
        }
    }

    void applyTextureState() {
        const int n = activeStages();
        for (int i = 0; i < units; ++i) {
            glActiveTexture(GL_TEXTURE0 + GLenum(i));
            for (GLenum t : {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP}) glDisable(t);
            for (GLenum g : {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q}) glDisable(g);
            if (i >= n) continue;
            const tex::StageState& st = stages[size_t(i)];
            // A stage without texture still runs its combiner (TEXTURE reads white): GL
            // needs an enabled target for that, so bind a 1×1 white texture.
            GLenum target = GL_TEXTURE_2D;
            GLuint name = 0;
            if (bound[size_t(i)]) {
                target = targetOf(trace.textures.at(bound[size_t(i)]).desc.target);
                name = textureName(bound[size_t(i)]);
            } else {
                static GLuint white = 0;
                if (!white) {
                    glGenTextures(1, &white);
                    glBindTexture(GL_TEXTURE_2D, white);
                    const uint8_t px[4] = {255, 255, 255, 255};
                    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
                }
                name = white;
            }
            glEnable(target);
            glBindTexture(target, name);
            const tex::SamplerState& s = samplers[size_t(i)];
            glTexParameteri(target, GL_TEXTURE_WRAP_S, GLint(wrap(s.address[0])));
            glTexParameteri(target, GL_TEXTURE_WRAP_T, GLint(wrap(s.address[1])));
            glTexParameteri(target, GL_TEXTURE_WRAP_R, GLint(wrap(s.address[2])));
            if (target == GL_TEXTURE_CUBE_MAP)
                for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
                    glTexParameteri(target, p, GL_CLAMP_TO_EDGE);
            glTexParameteri(target, GL_TEXTURE_MAG_FILTER, s.magFilter == tex::FilterMode::Linear ? GL_LINEAR : GL_NEAREST);
            GLint minf = s.minFilter == tex::FilterMode::Linear ? GL_LINEAR : GL_NEAREST;
            if (s.mipFilter == tex::MipMode::Nearest)
                minf = s.minFilter == tex::FilterMode::Linear ? GL_LINEAR_MIPMAP_NEAREST : GL_NEAREST_MIPMAP_NEAREST;
            if (s.mipFilter == tex::MipMode::Linear)
                minf = s.minFilter == tex::FilterMode::Linear ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST_MIPMAP_LINEAR;
            glTexParameteri(target, GL_TEXTURE_MIN_FILTER, minf);
            glTexParameterf(target, GL_TEXTURE_MIN_LOD, s.minLod);
            glTexParameterf(target, GL_TEXTURE_MAX_LOD, s.maxLod);
            glTexParameteri(target, GL_TEXTURE_BASE_LEVEL, s.baseLevel);
            const int levels = bound[size_t(i)] ? trace.textures.at(bound[size_t(i)]).desc.levels : 1;
            glTexParameteri(target, GL_TEXTURE_MAX_LEVEL, std::min(s.maxLevel, levels - 1));
            const float border[4] = {s.borderColor.r / 255.0f, s.borderColor.g / 255.0f, s.borderColor.b / 255.0f,
                                     s.borderColor.a / 255.0f};
            glTexParameterfv(target, GL_TEXTURE_BORDER_COLOR, border);
            glTexEnvf(GL_TEXTURE_FILTER_CONTROL, GL_TEXTURE_LOD_BIAS, s.lodBias);
            glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
            const float tf[4] = {tfactor.r / 255.0f, tfactor.g / 255.0f, tfactor.b / 255.0f, tfactor.a / 255.0f};
            glTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, tf);
            combineChannel(st.colorOp, st.colorArg1, st.colorArg2, st.colorArg0, st.colorScaleShift, false);
            combineChannel(st.alphaOp == tex::TextureOp::Disable ? tex::TextureOp::SelectArg2 : st.alphaOp,
                           st.alphaArg1, st.alphaArg2, st.alphaArg0, st.alphaScaleShift, true);
            // Coordinate generation of the set this stage reads; eye planes and the TCI
            // position mode are specified with an identity modelview (eye space).
            const tex::TexGenState& g = texGens[st.texCoordIndex];
            glMatrixMode(GL_TEXTURE);
            glLoadIdentity();
            if (g.matrixEnabled) glLoadMatrixf(&g.matrix[0][0]);
            glMatrixMode(GL_MODELVIEW);
            glPushMatrix();
            glLoadIdentity();
            const GLenum coords[4] = {GL_S, GL_T, GL_R, GL_Q};
            const GLenum enables[4] = {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q};
            auto gen = [&](int count, GLint mode) {
                for (int c = 0; c < count; ++c) {
                    glTexGeni(coords[c], GL_TEXTURE_GEN_MODE, mode);
                    glEnable(enables[c]);
                }
            };
            using tex::TexGenMode;
            switch (g.mode) {
                case TexGenMode::PassThru: break;
                case TexGenMode::CameraSpaceNormal: case TexGenMode::NormalMap: gen(3, GL_NORMAL_MAP); break;
                case TexGenMode::CameraSpaceReflectionVector: case TexGenMode::ReflectionMap: gen(3, GL_REFLECTION_MAP); break;
                case TexGenMode::SphereMap: gen(2, GL_SPHERE_MAP); break;
                case TexGenMode::CameraSpacePosition: {
                    const float planes[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
                    for (int c = 0; c < 3; ++c) glTexGenfv(coords[c], GL_EYE_PLANE, planes[c]);
                    gen(3, GL_EYE_LINEAR);
                    break;
                }
                case TexGenMode::ObjectLinear: case TexGenMode::EyeLinear: {
                    const bool eye = g.mode == TexGenMode::EyeLinear;
                    for (int c = 0; c < 4; ++c) glTexGenfv(coords[c], eye ? GL_EYE_PLANE : GL_OBJECT_PLANE, &g.planes[size_t(c)][0]);
                    gen(4, eye ? GL_EYE_LINEAR : GL_OBJECT_LINEAR);
                    break;
                }
            }
            glPopMatrix();
        }
        glActiveTexture(GL_TEXTURE0);
    }

    void applyTransform(VertexSpace space) {
        if (space == VertexSpace::Pretransformed) {
            // A square viewport of a power of two P ≥ the target: the ortho matrix scales by
            // 2/P and the viewport by P/2, so a window position comes back bit for bit
            // (glOrtho(0, w, …) with w = 30 moved vertices by an ulp, enough to flip ties).
            int P = 1;
            while (P < std::max(w, h)) P *= 2;
            glViewport(0, 0, P, P);
            glDepthRange(0, 1);
            const float k = 2.0f / float(P);
            const glm::mat4 m(glm::vec4(k, 0, 0, 0), glm::vec4(0, k, 0, 0), glm::vec4(0, 0, 1, 0),
                              glm::vec4(-1, -1, 0, 1));
            glMatrixMode(GL_PROJECTION);
            glLoadMatrixf(&m[0][0]);
            glMatrixMode(GL_MODELVIEW);
            glLoadIdentity();
        } else {
            glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
            glDepthRange(viewport.minZ, viewport.maxZ);
            // Clip y negated: our window row r is GL window row r (see the top of the file).
            glm::mat4 p = projection;
            for (int c = 0; c < 4; ++c) p[c][1] = -p[c][1];
            glMatrixMode(GL_PROJECTION);
            glLoadMatrixf(&p[0][0]);
            glMatrixMode(GL_MODELVIEW);
            glm::mat4 mv = view * world;
            glLoadMatrixf(&mv[0][0]);
        }
    }

    void vertex(const Vertex& v, VertexSpace space) {
        glColor4ub(v.diffuse.r, v.diffuse.g, v.diffuse.b, v.diffuse.a);
        glSecondaryColor3ub(v.specular.r, v.specular.g, v.specular.b);
        glNormal3f(v.normal.x, v.normal.y, v.normal.z);
        for (int s = 0; s < units; ++s) {
            glm::vec4 t = v.tex[size_t(s)];
            const tex::TexGenState& g = texGens[size_t(s)];
            // Without D3DTTFF_PROJECTED Direct3D ignores q; GL always divides by it.
            if (!g.projected) t.w = 1.0f;
            glMultiTexCoord4f(GL_TEXTURE0 + GLenum(s), t.x, t.y, t.z, t.w);
        }
        if (space == VertexSpace::Pretransformed) {
            const float iw = 1.0f / v.position.w;  // position.w is RHW
            glVertex4f(v.position.x * iw, v.position.y * iw, v.position.z * iw, iw);
        } else {
            glVertex4f(v.position.x, v.position.y, v.position.z, v.position.w);
        }
    }

    void draw(const TraceCommand& c) {
        applyFragmentState();
        applyTextureState();
        applyTransform(c.space);
        if (c.space == VertexSpace::Pretransformed) {
            // Ours draws pre-transformed triangles into viewport ∩ scissor too (docs/
            // trace-format.md, "Pre-transformed vertices"); GL's viewport is the window
            // here, so the scissor says it.
            int64_t x0 = viewport.x, y0 = viewport.y, x1 = int64_t(viewport.x) + viewport.width,
                    y1 = int64_t(viewport.y) + viewport.height;
            if (state.scissorTest) {
                x0 = std::max<int64_t>(x0, scissor.x); y0 = std::max<int64_t>(y0, scissor.y);
                x1 = std::min<int64_t>(x1, int64_t(scissor.x) + scissor.width);
                y1 = std::min<int64_t>(y1, int64_t(scissor.y) + scissor.height);
            }
            if (x1 <= x0 || y1 <= y0) return;
            glEnable(GL_SCISSOR_TEST);
            glScissor(GLint(x0), GLint(y0), GLsizei(x1 - x0), GLsizei(y1 - y0));
        }
        // Texture coordinates are submitted per coordinate set; stage i reads the set its
        // texCoordIndex names, so route set k to unit i through the GL unit's own
        // coordinate when they differ.
        std::vector<uint32_t> order;
        if (c.indices.empty())
            for (uint32_t i = 0; i < c.vertices.size(); ++i) order.push_back(i);
        else
            order = c.indices;
        const GLenum mode = c.primitive == Primitive::TriangleList    ? GL_TRIANGLES
                            : c.primitive == Primitive::TriangleStrip ? GL_TRIANGLE_STRIP
                                                                      : GL_TRIANGLE_FAN;
        glBegin(mode);
        for (uint32_t i : order) {
            if (i >= c.vertices.size()) continue;
            Vertex v = c.vertices[i];
            for (int s = 0; s < units; ++s) v.tex[size_t(s)] = c.vertices[i].tex[stages[size_t(s)].texCoordIndex];
            vertex(v, c.space);
        }
        glEnd();
    }

    void pixelOpsState() {
        for (GLenum e : {GL_DEPTH_TEST, GL_ALPHA_TEST, GL_BLEND, GL_SCISSOR_TEST, GL_CULL_FACE, GL_COLOR_SUM})
            glDisable(e);
        glColorMask(1, 1, 1, 1);
        for (int i = 0; i < units; ++i) {
            glActiveTexture(GL_TEXTURE0 + GLenum(i));
            for (GLenum t : {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP}) glDisable(t);
        }
        glActiveTexture(GL_TEXTURE0);
    }

    // The framebuffer at the start (docs/trace-format.md, "Framebuffer"): the record's
    // colour and depth, or all zero (a fresh OSMesa depth buffer is undefined).
    void initialContents() {
        pixelOpsState();
        glDepthMask(GL_TRUE);
        glClearColor(0, 0, 0, 0);
        glClearDepth(0.0);
        glClear(GL_COLOR_BUFFER_BIT | (trace.depth != DepthFormat::None ? GL_DEPTH_BUFFER_BIT : 0));
        glWindowPos2i(0, 0);
        glPixelZoom(1.0f, 1.0f);
        if (!trace.initialColor.empty())
            glDrawPixels(w, h, GL_RGBA, GL_UNSIGNED_BYTE, trace.initialColor.data());
        if (!trace.initialDepth.empty()) {
            // As 32-bit unsigned depth with the value's bits replicated, c/(2^32 − 1) is
            // exactly d/(2^n − 1), so the buffer stores d itself.
            const bool d16 = trace.depth == DepthFormat::D16;
            std::vector<uint32_t> z(trace.initialDepth.size());
            for (size_t i = 0; i < z.size(); ++i) {
                const uint32_t d = trace.initialDepth[i];
                z[i] = d16 ? (d << 16 | d) : (d << 8 | d >> 16);
            }
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(GL_ALWAYS);
            glColorMask(0, 0, 0, 0);
            glDrawPixels(w, h, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, z.data());
            glColorMask(1, 1, 1, 1);
            glDisable(GL_DEPTH_TEST);
        }
    }

    void play() {
        auto clipControl = reinterpret_cast<PFNGLCLIPCONTROLPROC>(OSMesaGetProcAddress("glClipControl"));
        if (!clipControl) throw Error("mesa replay: this Mesa has no glClipControl (ARB_clip_control)");
        clipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
        GLint u = 1;
        glGetIntegerv(GL_MAX_TEXTURE_UNITS, &u);
        units = std::min<int>(u, tex::kMaxTexCoordSets);
        viewport = {0, 0, w, h, 0, 1};
        scissor = {0, 0, w, h};
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        initialContents();
        for (const TraceCommand& c : trace.commands) {
            switch (c.op) {
                case TraceOp::State: state = c.state; break;
                case TraceOp::Transforms: world = c.world; view = c.view; projection = c.projection; break;
                case TraceOp::Viewport: viewport = c.viewport; break;
                case TraceOp::Scissor: scissor = c.rect; break;
                case TraceOp::Stage: stages[size_t(c.unit)] = c.stage; break;
                case TraceOp::Sampler: samplers[size_t(c.unit)] = c.sampler; break;
                case TraceOp::TextureFactor: tfactor = c.color; break;
                case TraceOp::TexGen: texGens[size_t(c.unit)] = c.texGen; break;
                case TraceOp::BindTexture: bound[size_t(c.unit)] = c.textureId; break;
                case TraceOp::Clear: {
                    // D3D7 Clear: the viewport (∩ scissor when enabled), colour unmasked.
                    int64_t x0 = viewport.x, y0 = viewport.y, x1 = int64_t(viewport.x) + viewport.width,
                            y1 = int64_t(viewport.y) + viewport.height;
                    if (state.scissorTest) {
                        x0 = std::max<int64_t>(x0, scissor.x); y0 = std::max<int64_t>(y0, scissor.y);
                        x1 = std::min<int64_t>(x1, int64_t(scissor.x) + scissor.width);
                        y1 = std::min<int64_t>(y1, int64_t(scissor.y) + scissor.height);
                    }
                    if (x1 <= x0 || y1 <= y0) break;
                    glEnable(GL_SCISSOR_TEST);
                    glScissor(GLint(x0), GLint(y0), GLsizei(x1 - x0), GLsizei(y1 - y0));
                    glColorMask(1, 1, 1, 1);
                    glDepthMask(GL_TRUE);
                    glClearColor(c.color.r / 255.0f, c.color.g / 255.0f, c.color.b / 255.0f, c.color.a / 255.0f);
                    glClearDepth(c.depthValue);
                    glClear((c.clearColor ? GL_COLOR_BUFFER_BIT : 0) |
                            (c.clearDepth && trace.depth != DepthFormat::None ? GL_DEPTH_BUFFER_BIT : 0));
                    break;
                }
                case TraceOp::Draw: draw(c); break;
                case TraceOp::DrawPixels:
                    pixelOpsState();
                    glPixelZoom(1.0f, 1.0f);
                    glWindowPos2i(c.rect.x, c.rect.y);
                    glDrawPixels(c.rect.width, c.rect.height, GL_RGBA, GL_UNSIGNED_BYTE, c.pixels.data());
                    break;
                case TraceOp::CopyPixels:
                    pixelOpsState();
                    glPixelZoom(1.0f, 1.0f);
                    glWindowPos2i(c.dstX, c.dstY);
                    glCopyPixels(c.rect.x, c.rect.y, c.rect.width, c.rect.height, GL_COLOR);
                    break;
                case TraceOp::ReadPixels: {
                    // Not compared (the capture's hash is of our pixels), but read all the
                    // same: a read-back drains the pipeline, which `bench --trace` must
                    // charge to Mesa as the replay on ours is charged for it.
                    readBack.resize(size_t(c.rect.width) * size_t(c.rect.height) * 4);
                    glReadPixels(c.rect.x, c.rect.y, c.rect.width, c.rect.height, GL_RGBA,
                                 GL_UNSIGNED_BYTE, readBack.data());
                    break;
                }
                default: break;
            }
        }
        glFinish();
    }

    // Deletes the textures play() made, so that the next play uploads them again.
    void release() {
        for (const auto& [id, name] : names) glDeleteTextures(1, &name);
        names.clear();
    }
};

}  // namespace

void playOnCurrentContext(const Trace& trace) {
    if (trace.programmable) {
        detail::playProgramTrace(trace, nullptr);
        return;
    }
    // Row 0 of the buffer is GL's window row 0, which the player makes our row 0 (the top).
    OSMesaPixelStore(OSMESA_Y_UP, 1);
    GlPlayer p(trace);
    p.play();
    p.release();
}

std::string mesaUnsupported(const Trace& trace) {
    if (trace.programmable) return detail::mesaProgramUnsupported(trace);
    for (const auto& [id, t] : trace.textures) {
        if (t.desc.target == tex::TextureTarget::Texture4D) return "4D textures (SGIS_texture4D)";
        if (tex::formatInfo(t.desc.format).isFloat) return "float and depth textures";
    }
    std::array<tex::StageState, tex::kMaxStages> stages{};
    PipelineState state;
    for (const TraceCommand& c : trace.commands) {
        switch (c.op) {
            case TraceOp::State: state = c.state; break;
            case TraceOp::ColorTable:
                if (c.colorTable) return "texture colour tables (SGI_texture_color_table)";
                break;
            case TraceOp::PixelTexture:
                if (c.pixelTexture.enabled) return "pixel texture (SGIX_pixel_texture)";
                break;
            case TraceOp::Stage: stages[size_t(c.unit)] = c.stage; break;
            case TraceOp::Draw:
                if (!state.perspectiveColor)
                    return "colours interpolated without perspective correction (GL always corrects)";
                for (int i = 0; i < tex::kMaxStages && stages[size_t(i)].colorOp != tex::TextureOp::Disable; ++i) {
                    if (i >= 8) return "more than 8 texture stages (GL_MAX_TEXTURE_UNITS of llvmpipe's fixed function)";
                    const tex::StageState& s = stages[size_t(i)];
                    for (tex::TextureOp op : {s.colorOp, s.alphaOp})
                        if (!glOpExpressible(op))
                            return "D3DTOP_" + std::string(tex::textureOpName(op)) + " (no GL 1.3 combine twin)";
                    for (uint8_t a : {s.colorArg0, s.colorArg1, s.colorArg2, s.alphaArg0, s.alphaArg1, s.alphaArg2})
                        if ((a & tex::arg::SourceMask) == tex::arg::Specular)
                            return "D3DTA_SPECULAR as a stage argument";
                }
                break;
            default: break;
        }
    }
    return {};
}

std::string oursOnlyReason(const Trace& trace) {
    const std::string missing = mesaUnsupported(trace);
    if (missing.empty()) return {};
    // A programmable trace's reasons are whole phrases (a program without a twin is not
    // something Mesa lacks); the fixed-function ones name a GL feature.
    return trace.programmable ? missing : "Mesa lacks " + missing;
}

MesaReplay replayOnMesa(const Trace& trace) {
    MesaReplay out;
    out.unsupported = mesaUnsupported(trace);
    if (!out.unsupported.empty()) return out;
    int fds[2];
    if (::pipe(fds) != 0) throw Error("mesa replay: pipe failed");
    const pid_t pid = ::fork();
    if (pid < 0) throw Error("mesa replay: fork failed");
    const size_t n = size_t(trace.width) * size_t(trace.height) * 4;
    if (pid == 0) {
        // The child answers [u32 0][u32 length][GL_RENDERER][the image] or [u32 1][u32
        // length][the error]; it never returns into the caller's code.
        ::close(fds[0]);
        ::setenv("GALLIUM_DRIVER", "llvmpipe", 1);
        ::setenv("LP_NUM_THREADS", "1", 1);
        const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS,
                               trace.depth == DepthFormat::D16 ? 16 : 24, OSMESA_STENCIL_BITS, 0,
                               OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0};
        OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
        // A programmable trace renders into framebuffer objects; the window is a token.
        const int bw = std::max(1, trace.width), bh = std::max(1, trace.height);
        std::vector<uint8_t> buffer(size_t(bw) * size_t(bh) * 4);
        uint32_t status = 1;
        std::string text = "cannot create an OSMesa context";
        try {
            if (ctx && OSMesaMakeCurrent(ctx, buffer.data(), GL_UNSIGNED_BYTE, bw, bh)) {
                if (trace.programmable) {
                    std::vector<Rgba8> image;
                    detail::playProgramTrace(trace, &image);
                    if (image.size() * 4 == n) std::memcpy(buffer.data(), image.data(), n);
                } else {
                    playOnCurrentContext(trace);
                }
                const GLubyte* r = glGetString(GL_RENDERER);
                text = r ? reinterpret_cast<const char*>(r) : "unknown";
                status = 0;
            }
        } catch (const std::exception& e) {
            text = e.what();
        }
        const uint32_t len = uint32_t(text.size());
        bool ok = io::writeAll(fds[1], &status, 4) && io::writeAll(fds[1], &len, 4) &&
                  io::writeAll(fds[1], text.data(), len);
        if (ok && status == 0) io::writeAll(fds[1], buffer.data(), n);
        if (ctx) OSMesaDestroyContext(ctx);
        ::_exit(int(status));
    }
    ::close(fds[1]);
    uint32_t childStatus = 1, len = 0;
    std::string text;
    bool ok = io::readAll(fds[0], &childStatus, 4) && io::readAll(fds[0], &len, 4) && len < (1u << 16);
    if (ok) {
        text.resize(len);
        ok = io::readAll(fds[0], text.data(), len);
    }
    if (ok && childStatus == 0) {
        out.renderer = text;
        if (trace.width > 0 && trace.height > 0) {
            out.framebuffer = Framebuffer(trace.width, trace.height, DepthFormat::None);
            ok = io::readAll(fds[0], out.framebuffer.color().data(), n);
        }
    }
    ::close(fds[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (ok && childStatus != 0) throw Error("mesa replay: " + text);
    if (!ok) throw Error("mesa replay: the OSMesa child failed (status " + std::to_string(status) + ")");
    return out;
}

}  // namespace rg::conformance

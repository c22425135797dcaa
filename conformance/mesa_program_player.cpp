// The Mesa peer of a programmable trace: the records through OpenGL 3 on OSMesa (llvmpipe),
// each draw through the GLSL twin registered under its program's name.
//
// What maps how (Direct3D 10 / our device → GL):
//   window origin, clip z     glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE): clip y = +1 is
//                              window row 0, the first row of a target's storage, as ours;
//                              gl_FragCoord is our fragCoord(); clip z ∈ [0, w]. Viewport
//                              and scissor rectangles pass unchanged, and a later pass
//                              samples a target row for row as ours does
//   cull                      the area's sign is negated under GL_UPPER_LEFT, so GL's facing
//                              is the winding seen on screen, as ours: CW culls GL_BACK with
//                              GL_CCW front (the fixed-function player's mapping)
//   depth                     our depth write without the depth test: GL_ALWAYS (GL writes
//                              depth only with the test enabled)
//   clears                    viewport ∩ scissor as the scissor rectangle, every channel
//   blend, write mask         per target (glBlendFunci, glBlendEquationi, glColorMaski);
//                              BOTHSRCALPHA as (SRC_ALPHA, ONE_MINUS_SRC_ALPHA)
//   textures                  packed texels as GL uploads them (8-bit formats expanded to
//                              RGBA8 with the base format's internal format, halves as
//                              GL_HALF_FLOAT, depth as float); samplers as sampler objects
//   render targets            GL textures of the same format, allocated with their trace
//                              contents (or zero), one framebuffer object per binding
#include "mesa_program_player.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <memory>

#include "core/error.h"
#include "rasterizer/program_registry.h"
#include "texunit/format.h"

namespace rg::conformance::detail {

using namespace rg::raster;

namespace {

void checkGl(const char* where) {
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        throw Error(std::string("mesa program replay: GL error ") + std::to_string(e) + " at " + where);
}

GLenum compare(CompareFunc f) { return GL_NEVER + GLenum(f); }  // the same order as GL

GLenum blendFactor(BlendFactor f) {
    switch (f) {
        case BlendFactor::Zero: return GL_ZERO;
        case BlendFactor::One: return GL_ONE;
        case BlendFactor::SrcColor: return GL_SRC_COLOR;
        case BlendFactor::InvSrcColor: return GL_ONE_MINUS_SRC_COLOR;
        case BlendFactor::SrcAlpha: case BlendFactor::BothSrcAlpha: return GL_SRC_ALPHA;
        case BlendFactor::InvSrcAlpha: case BlendFactor::BothInvSrcAlpha: return GL_ONE_MINUS_SRC_ALPHA;
        case BlendFactor::DestAlpha: return GL_DST_ALPHA;
        case BlendFactor::InvDestAlpha: return GL_ONE_MINUS_DST_ALPHA;
        case BlendFactor::DestColor: return GL_DST_COLOR;
        case BlendFactor::InvDestColor: return GL_ONE_MINUS_DST_COLOR;
        case BlendFactor::SrcAlphaSat: return GL_SRC_ALPHA_SATURATE;
    }
    return GL_ONE;
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
        case tex::AddressMode::Clamp: return GL_CLAMP_TO_EDGE;  // no GL_CLAMP in a sampler object
        case tex::AddressMode::ClampToEdge: return GL_CLAMP_TO_EDGE;
        case tex::AddressMode::Border: return GL_CLAMP_TO_BORDER;
    }
    return GL_REPEAT;
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

// How a texel format goes to GL: internal format, and the format and type of the data
// the player uploads (`expand8`: 8-bit texels expanded to RGBA8 first; `depthFloat`:
// depth expanded to float first).
struct GlFormat {
    GLenum internal, format, type;
    bool expand8 = false, depthFloat = false;
};

GlFormat glFormat(tex::TexelFormat f) {
    using tex::TexelFormat;
    switch (f) {
        case TexelFormat::RGBA8: return {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
        case TexelFormat::R16F: return {GL_R16F, GL_RED, GL_HALF_FLOAT};
        case TexelFormat::RGBA16F: return {GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT};
        case TexelFormat::R32F: return {GL_R32F, GL_RED, GL_FLOAT};
        case TexelFormat::RGBA32F: return {GL_RGBA32F, GL_RGBA, GL_FLOAT};
        case TexelFormat::Depth16: return {GL_DEPTH_COMPONENT16, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT};
        case TexelFormat::Depth24: return {GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_FLOAT, false, true};
        case TexelFormat::Depth32F: return {GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT};
        default: break;
    }
    // L8, A8, L8A8, I8, RGB565, RGBA4444, RGB8: expanded, stored as their base format.
    GLenum internal = GL_RGBA8;
    switch (tex::formatInfo(f).base) {
        case tex::BaseFormat::Alpha: internal = GL_ALPHA8; break;
        case tex::BaseFormat::Luminance: internal = GL_LUMINANCE8; break;
        case tex::BaseFormat::LuminanceAlpha: internal = GL_LUMINANCE8_ALPHA8; break;
        case tex::BaseFormat::Intensity: internal = GL_INTENSITY8; break;
        case tex::BaseFormat::Rgb: internal = GL_RGB8; break;
        case tex::BaseFormat::Rgba: internal = GL_RGBA8; break;
    }
    return {internal, GL_RGBA, GL_UNSIGNED_BYTE, true};
}

// The format of a render target's stored values (renderTargetValues()).
GlFormat glTargetFormat(tex::TexelFormat f) {
    using tex::TexelFormat;
    switch (f) {
        case TexelFormat::R16F: return {GL_R16F, GL_RED, GL_FLOAT};
        case TexelFormat::RGBA16F: return {GL_RGBA16F, GL_RGBA, GL_FLOAT};
        case TexelFormat::Depth24: return {GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_FLOAT};
        default: return glFormat(f);  // RGBA8, R32F, RGBA32F, Depth32F as stored
    }
}

// glTexImage of one level of one face of any target.
void texImage(GLenum target, int face, int level, const GlFormat& g, int w, int h, int d, const void* data) {
    switch (target) {
        case GL_TEXTURE_1D:
            glTexImage1D(target, level, GLint(g.internal), w, 0, g.format, g.type, data);
            break;
        case GL_TEXTURE_3D:
            glTexImage3D(target, level, GLint(g.internal), w, h, d, 0, g.format, g.type, data);
            break;
        case GL_TEXTURE_CUBE_MAP:
            glTexImage2D(GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face), level, GLint(g.internal), w, h, 0, g.format,
                         g.type, data);
            break;
        default: glTexImage2D(target, level, GLint(g.internal), w, h, 0, g.format, g.type, data); break;
    }
}

class Uniforms final : public GlslUniforms {
  public:
    explicit Uniforms(GLuint program) : program_(program) {}
    void setFloat(std::string_view name, int components, std::span<const float> v) override {
        const GLint at = location(name);
        if (at < 0 || components < 1 || components > 4) return;
        const GLsizei n = GLsizei(v.size() / size_t(components));
        switch (components) {
            case 1: glUniform1fv(at, n, v.data()); break;
            case 2: glUniform2fv(at, n, v.data()); break;
            case 3: glUniform3fv(at, n, v.data()); break;
            default: glUniform4fv(at, n, v.data()); break;
        }
    }
    void setInt(std::string_view name, std::span<const int32_t> v) override {
        if (const GLint at = location(name); at >= 0) glUniform1iv(at, GLsizei(v.size()), v.data());
    }
    void setMat4(std::string_view name, std::span<const float> v) override {
        if (const GLint at = location(name); at >= 0) glUniformMatrix4fv(at, GLsizei(v.size() / 16), GL_FALSE, v.data());
    }

  private:
    GLint location(std::string_view name) const { return glGetUniformLocation(program_, std::string(name).c_str()); }
    GLuint program_;
};

GLuint compileShader(GLenum kind, const std::string& source, const std::string& program) {
    GLuint shader = glCreateShader(kind);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        throw Error("the GLSL twin of program '" + program + "': the " +
                    (kind == GL_VERTEX_SHADER ? "vertex" : "fragment") + " shader does not compile: " + log);
    }
    return shader;
}

// A twin's linked program, kept for the life of the context (the process: one OSMesa
// context per child).
GLuint linkedTwin(const std::string& name, const GlslTwin& twin) {
    static std::map<std::pair<OSMesaContext, std::string>, GLuint> cache;
    const auto key = std::make_pair(OSMesaGetCurrentContext(), name);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
    const GLuint vs = compileShader(GL_VERTEX_SHADER, twin.vertexShader, name);
    const GLuint fs = compileShader(GL_FRAGMENT_SHADER, twin.fragmentShader, name);
    const GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    for (size_t i = 0; i < twin.attributes.size(); ++i)
        glBindAttribLocation(program, GLuint(i), twin.attributes[i].name.c_str());
    for (size_t k = 0; k < twin.outputs.size(); ++k)
        if (!twin.outputs[k].empty()) glBindFragDataLocation(program, GLuint(k), twin.outputs[k].c_str());
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked) {
        char log[2048] = {};
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        glDeleteProgram(program);
        throw Error("the GLSL twin of program '" + name + "' does not link: " + log);
    }
    glUseProgram(program);
    for (size_t u = 0; u < twin.samplers.size(); ++u)
        if (!twin.samplers[u].empty())
            if (const GLint at = glGetUniformLocation(program, twin.samplers[u].c_str()); at >= 0)
                glUniform1i(at, GLint(u));
    checkGl("linking a GLSL twin");
    cache.emplace(key, program);
    return program;
}

struct ProgramPlayer {
    explicit ProgramPlayer(const Trace& t) : trace(t) {}
    const Trace& trace;
    std::map<uint64_t, GLuint> textures;  // textures and render targets by trace id
    std::vector<GLuint> framebuffers, samplers, buffers, arrays;
    std::vector<TraceTargetBinding> colors;
    TraceTargetBinding depth;
    GLuint framebuffer = 0;
    int width = 0, height = 0;
    ProgramState state;
    Viewport viewport;
    bool scissorOn = false;
    Rect scissor;
    struct Unit {
        uint64_t id = 0;
        tex::SamplerState sampler;
    };
    std::array<Unit, kMaxProgramUnits> units{};

    GLuint texture(uint64_t id) {
        if (auto it = textures.find(id); it != textures.end()) return it->second;
        GLuint name = 0;
        glGenTextures(1, &name);
        textures.emplace(id, name);
        if (auto rt = trace.renderTargets.find(id); rt != trace.renderTargets.end()) {
            const tex::TextureDesc& d = rt->second.desc;
            const GLenum target = targetOf(d.target);
            glBindTexture(target, name);
            const GlFormat g = glTargetFormat(d.format);
            const int faces = d.target == tex::TextureTarget::CubeMap ? 6 : 1;
            const size_t perTexel = !tex::formatInfo(d.format).isFloat ? 4 : (g.format == GL_RGBA ? 16 : 4);
            size_t at = 0;
            for (int l = 0; l < d.levels; ++l) {
                const int w = std::max(1, d.width >> l), h = target == GL_TEXTURE_1D ? 1 : std::max(1, d.height >> l);
                const size_t n = size_t(w) * size_t(h) * perTexel;
                std::vector<uint8_t> zero;
                for (int f = 0; f < faces; ++f) {
                    const void* data = nullptr;
                    if (!rt->second.contents.empty()) {
                        data = rt->second.contents.data() + at;
                    } else {
                        zero.assign(n, 0);  // GL leaves a new texture's contents undefined
                        data = zero.data();
                    }
                    at += n;
                    texImage(target, f, l, g, w, h, 1, data);
                }
            }
            glTexParameteri(target, GL_TEXTURE_MAX_LEVEL, d.levels - 1);
        } else {
            const TraceTexture& t = trace.textures.at(id);
            const tex::TextureDesc& d = t.desc;
            const GLenum target = targetOf(d.target);
            glBindTexture(target, name);
            const GlFormat g = glFormat(d.format);
            const int faces = d.target == tex::TextureTarget::CubeMap ? 6 : 1;
            const int bpt = tex::formatInfo(d.format).bytesPerTexel;
            for (int l = 0; l < d.levels; ++l)
                for (int f = 0; f < faces; ++f) {
                    const std::vector<uint8_t>& packed = t.levelFaces[size_t(l * faces + f)];
                    const size_t n = packed.size() / size_t(bpt);
                    std::vector<Rgba8> rgba;
                    std::vector<float> depthValues;
                    const void* data = packed.data();
                    if (g.expand8) {
                        rgba.resize(n);
                        for (size_t i = 0; i < n; ++i) rgba[i] = tex::expandTexel8(d.format, packed.data() + i * size_t(bpt));
                        data = rgba.data();
                    } else if (g.depthFloat) {
                        depthValues.resize(n);
                        for (size_t i = 0; i < n; ++i)
                            depthValues[i] = tex::expandTexelFloat(d.format, packed.data() + i * size_t(bpt)).x;
                        data = depthValues.data();
                    }
                    texImage(target, f, l, g, std::max(1, d.width >> l), std::max(1, d.height >> l),
                             std::max(1, d.depth >> l), data);
                }
            glTexParameteri(target, GL_TEXTURE_MAX_LEVEL, d.levels - 1);
        }
        checkGl("a texture upload");
        return name;
    }

    const tex::TextureDesc& descOf(uint64_t id) const {
        if (auto rt = trace.renderTargets.find(id); rt != trace.renderTargets.end()) return rt->second.desc;
        return trace.textures.at(id).desc;
    }

    void attach(GLenum attachment, const TraceTargetBinding& b) {
        const tex::TextureDesc& d = descOf(b.id);
        const GLuint name = texture(b.id);
        if (d.target == tex::TextureTarget::Texture1D)
            glFramebufferTexture1D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_1D, name, b.level);
        else if (d.target == tex::TextureTarget::CubeMap)
            glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + b.face), name,
                                   b.level);
        else
            glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_2D, name, b.level);
    }

    void bindTargets(const TraceCommand& c) {
        colors = c.colorTargets;
        depth = c.depthTarget;
        glGenFramebuffers(1, &framebuffer);
        framebuffers.push_back(framebuffer);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        std::vector<GLenum> draw;
        for (size_t k = 0; k < colors.size(); ++k) {
            attach(GLenum(GL_COLOR_ATTACHMENT0 + k), colors[k]);
            draw.push_back(GLenum(GL_COLOR_ATTACHMENT0 + k));
        }
        if (depth.id) attach(GL_DEPTH_ATTACHMENT, depth);
        if (draw.empty())
            glDrawBuffer(GL_NONE);
        else
            glDrawBuffers(GLsizei(draw.size()), draw.data());
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw Error("mesa program replay: a RenderTargets binding is not a complete framebuffer object");
        const TraceTargetBinding& first = colors.empty() ? depth : colors[0];
        const tex::TextureDesc& d = descOf(first.id);
        width = std::max(1, d.width >> first.level);
        height = d.target == tex::TextureTarget::Texture1D ? 1 : std::max(1, d.height >> first.level);
        // What setRenderTargets resets on ours.
        viewport = {0, 0, width, height, 0.0f, 1.0f};
        scissorOn = false;
        checkGl("binding render targets");
    }

    // Viewport ∩ scissor as a GL scissor rectangle; false when empty.
    bool clearRect() {
        int64_t x0 = viewport.x, y0 = viewport.y, x1 = int64_t(viewport.x) + viewport.width,
                y1 = int64_t(viewport.y) + viewport.height;
        if (scissorOn) {
            x0 = std::max<int64_t>(x0, scissor.x);
            y0 = std::max<int64_t>(y0, scissor.y);
            x1 = std::min<int64_t>(x1, int64_t(scissor.x) + scissor.width);
            y1 = std::min<int64_t>(y1, int64_t(scissor.y) + scissor.height);
        }
        if (x1 <= x0 || y1 <= y0) return false;
        glEnable(GL_SCISSOR_TEST);
        glScissor(GLint(x0), GLint(y0), GLsizei(x1 - x0), GLsizei(y1 - y0));
        return true;
    }

    void applyState() {
        glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
        glDepthRange(viewport.minZ, viewport.maxZ);
        if (scissorOn) {
            glEnable(GL_SCISSOR_TEST);
            glScissor(scissor.x, scissor.y, scissor.width, scissor.height);
        } else {
            glDisable(GL_SCISSOR_TEST);
        }
        if (state.cull == CullMode::None) {
            glDisable(GL_CULL_FACE);
        } else {
            glEnable(GL_CULL_FACE);
            glFrontFace(GL_CCW);
            glCullFace(state.cull == CullMode::CW ? GL_BACK : GL_FRONT);
        }
        if (depth.id && (state.depthTest || state.depthWrite)) {
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(state.depthTest ? compare(state.depthFunc) : GL_ALWAYS);
            glDepthMask(state.depthWrite ? GL_TRUE : GL_FALSE);
        } else {
            glDisable(GL_DEPTH_TEST);
        }
        for (size_t k = 0; k < colors.size(); ++k) {
            const TargetBlend& b = state.blend[k];
            const GLuint i = GLuint(k);
            b.enable ? glEnablei(GL_BLEND, i) : glDisablei(GL_BLEND, i);
            GLenum src = blendFactor(b.src), dst = blendFactor(b.dst);
            if (b.src == BlendFactor::BothSrcAlpha) dst = GL_ONE_MINUS_SRC_ALPHA;
            if (b.src == BlendFactor::BothInvSrcAlpha) dst = GL_SRC_ALPHA;
            glBlendFunci(i, src, dst);
            glBlendEquationi(i, blendEquation(b.op));
            glColorMaski(i, b.writeMask & kWriteR, b.writeMask & kWriteG, b.writeMask & kWriteB, b.writeMask & kWriteA);
        }
        glPointSize(state.pointSize);
    }

    void bindUnit(int u) {
        const Unit& unit = units[size_t(u)];
        glActiveTexture(GLenum(GL_TEXTURE0 + u));
        if (!unit.id) return;
        const tex::TextureDesc& d = descOf(unit.id);
        const GLenum target = targetOf(d.target);
        glBindTexture(target, texture(unit.id));
        const tex::SamplerState& s = unit.sampler;
        glTexParameteri(target, GL_TEXTURE_BASE_LEVEL, std::clamp(s.baseLevel, 0, d.levels - 1));
        glTexParameteri(target, GL_TEXTURE_MAX_LEVEL, std::clamp(s.maxLevel, 0, d.levels - 1));
        GLuint sampler = 0;
        glGenSamplers(1, &sampler);
        samplers.push_back(sampler);
        glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GLint(wrap(s.address[0])));
        glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GLint(wrap(s.address[1])));
        glSamplerParameteri(sampler, GL_TEXTURE_WRAP_R, GLint(wrap(s.address[2])));
        glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, s.magFilter == tex::FilterMode::Linear ? GL_LINEAR : GL_NEAREST);
        const bool linear = s.minFilter == tex::FilterMode::Linear;
        GLint minf = linear ? GL_LINEAR : GL_NEAREST;
        if (s.mipFilter == tex::MipMode::Nearest) minf = linear ? GL_LINEAR_MIPMAP_NEAREST : GL_NEAREST_MIPMAP_NEAREST;
        if (s.mipFilter == tex::MipMode::Linear) minf = linear ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST_MIPMAP_LINEAR;
        glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, minf);
        glSamplerParameterf(sampler, GL_TEXTURE_MIN_LOD, s.minLod);
        glSamplerParameterf(sampler, GL_TEXTURE_MAX_LOD, s.maxLod);
        glSamplerParameterf(sampler, GL_TEXTURE_LOD_BIAS, s.lodBias);
        const float border[4] = {s.borderColor.r / 255.0f, s.borderColor.g / 255.0f, s.borderColor.b / 255.0f,
                                 s.borderColor.a / 255.0f};
        glSamplerParameterfv(sampler, GL_TEXTURE_BORDER_COLOR, border);
        glBindSampler(GLuint(u), sampler);
    }

    void draw(const TraceCommand& c) {
        const TraceProgramDraw& d = c.programDraw;
        const GlslTwin& twin = *findGlslTwin(d.program->name);
        const GLuint program = linkedTwin(d.program->name, twin);
        glUseProgram(program);
        if (twin.uniforms) {
            Uniforms u(program);
            twin.uniforms(d.vertexProgram, d.fragmentProgram, u);
        }
        applyState();
        for (int u = 0; u < kMaxProgramUnits; ++u)
            if ((d.program->units >> u) & 1u) {
                bindUnit(u);
                if (u < int(twin.compareSamplers.size()) && twin.compareSamplers[size_t(u)]) {
                    glSamplerParameteri(samplers.back(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
                    glSamplerParameteri(samplers.back(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);  // ref ≤ depth passes
                }
            }
        GLuint vao = 0, vbo = 0;
        glGenVertexArrays(1, &vao);
        arrays.push_back(vao);
        glBindVertexArray(vao);
        glGenBuffers(1, &vbo);
        buffers.push_back(vbo);
        glBindBuffer(GL_ARRAY_BUFFER, vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(d.vertices.size()), d.vertices.data(), GL_STATIC_DRAW);
        const GLsizei stride = GLsizei(d.program->vertexBytes);
        for (size_t i = 0; i < twin.attributes.size(); ++i) {
            const GlslAttribute& a = twin.attributes[i];
            glVertexAttribPointer(GLuint(i), a.components, GL_FLOAT, GL_FALSE, stride,
                                  reinterpret_cast<const void*>(uintptr_t(a.offset)));
            glEnableVertexAttribArray(GLuint(i));
        }
        const GLenum mode = d.primitive == ProgramPrimitive::TriangleList    ? GL_TRIANGLES
                            : d.primitive == ProgramPrimitive::TriangleStrip ? GL_TRIANGLE_STRIP
                            : d.primitive == ProgramPrimitive::TriangleFan   ? GL_TRIANGLE_FAN
                                                                             : GL_POINTS;
        if (c.indices.empty()) {
            glDrawArrays(mode, 0, GLsizei(d.vertexCount));
        } else {
            GLuint ebo = 0;
            glGenBuffers(1, &ebo);
            buffers.push_back(ebo);
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
            glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(c.indices.size() * 4), c.indices.data(), GL_STATIC_DRAW);
            glDrawElements(mode, GLsizei(c.indices.size()), GL_UNSIGNED_INT, nullptr);
        }
        glBindVertexArray(0);
        checkGl("a draw");
    }

    void play() {
        auto clipControl = reinterpret_cast<PFNGLCLIPCONTROLPROC>(OSMesaGetProcAddress("glClipControl"));
        if (!clipControl) throw Error("mesa program replay: this Mesa has no glClipControl (ARB_clip_control)");
        clipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE);
        glDisable(GL_DITHER);
        glEnable(GL_POINT_SPRITE);  // gl_PointCoord (always on in a core profile)
        glDisable(GL_PROGRAM_POINT_SIZE);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        for (const TraceCommand& c : trace.commands) {
            switch (c.op) {
                case TraceOp::RenderTargets: bindTargets(c); break;
                case TraceOp::ProgramState: state = c.programState; break;
                case TraceOp::Viewport: viewport = c.viewport; break;
                case TraceOp::ProgramScissor:
                    scissorOn = c.scissorOn;
                    scissor = c.rect;
                    break;
                case TraceOp::ProgramTexture: units[size_t(c.unit)] = {c.textureId, c.sampler}; break;
                case TraceOp::ClearTarget:
                    if (clearRect()) {
                        glColorMaski(GLuint(c.unit), 1, 1, 1, 1);
                        glClearBufferfv(GL_COLOR, c.unit, &c.clearValue.x);
                    }
                    checkGl("a colour clear");
                    break;
                case TraceOp::ClearDepth:
                    if (clearRect()) {
                        glDepthMask(GL_TRUE);
                        glClearBufferfv(GL_DEPTH, 0, &c.depthValue);
                    }
                    checkGl("a depth clear");
                    break;
                case TraceOp::ProgramDraw: draw(c); break;
                default: break;  // BeginFrame: counters only
            }
        }
        glFinish();
    }

    // The image (colour target 0 of the last binding) as RGBA8, rows top to bottom.
    std::vector<Rgba8> readImage() {
        std::vector<Rgba8> out;
        if (!trace.image.id) return out;
        GLuint fbo = 0;
        glGenFramebuffers(1, &fbo);
        framebuffers.push_back(fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        attach(GL_COLOR_ATTACHMENT0, trace.image);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        const size_t n = size_t(trace.width) * size_t(trace.height);
        out.resize(n);
        if (!tex::formatInfo(descOf(trace.image.id).format).isFloat) {
            glReadPixels(0, 0, trace.width, trace.height, GL_RGBA, GL_UNSIGNED_BYTE, out.data());
        } else {
            std::vector<glm::vec4> v(n);
            glReadPixels(0, 0, trace.width, trace.height, GL_RGBA, GL_FLOAT, v.data());
            for (size_t i = 0; i < n; ++i) out[i] = tex::floatToRgba8(v[i]);
        }
        checkGl("reading the image back");
        return out;
    }

    void release() {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glUseProgram(0);
        for (int u = 0; u < kMaxProgramUnits; ++u) glBindSampler(GLuint(u), 0);
        for (const auto& [id, name] : textures) glDeleteTextures(1, &name);
        if (!framebuffers.empty()) glDeleteFramebuffers(GLsizei(framebuffers.size()), framebuffers.data());
        if (!samplers.empty()) glDeleteSamplers(GLsizei(samplers.size()), samplers.data());
        if (!buffers.empty()) glDeleteBuffers(GLsizei(buffers.size()), buffers.data());
        if (!arrays.empty()) glDeleteVertexArrays(GLsizei(arrays.size()), arrays.data());
        textures.clear();
        framebuffers.clear();
        samplers.clear();
        buffers.clear();
        arrays.clear();
    }
};

}  // namespace

std::string mesaProgramUnsupported(const Trace& trace) {
    for (const auto& [id, t] : trace.textures)
        if (t.desc.target == tex::TextureTarget::Texture4D) return "Mesa lacks 4D textures (SGIS_texture4D)";
    for (const TraceCommand& c : trace.commands) {
        if (c.op != TraceOp::ProgramDraw) continue;
        const RegisteredProgram& p = *c.programDraw.program;
        const GlslTwin* twin = findGlslTwin(p.name);
        if (!twin) return "no GLSL twin registered for program '" + p.name + "'";
        for (int u = 0; u < kMaxProgramUnits; ++u)
            if (((p.units >> u) & 1u) && (u >= int(twin->samplers.size()) || twin->samplers[size_t(u)].empty()))
                return "the GLSL twin of program '" + p.name + "' names no sampler for unit " + std::to_string(u);
        for (int k = 0; k < kMaxColorTargets; ++k)
            if (((p.targets >> k) & 1u) && (k >= int(twin->outputs.size()) || twin->outputs[size_t(k)].empty()))
                return "the GLSL twin of program '" + p.name + "' names no output for target " + std::to_string(k);
        for (const GlslAttribute& a : twin->attributes)
            if (a.components < 1 || a.components > 4 || uint64_t(a.offset) + 4u * uint64_t(a.components) > p.vertexBytes)
                return "the GLSL twin of program '" + p.name + "' reads attribute '" + a.name + "' past its vertex";
    }
    return {};
}

void playProgramTrace(const Trace& trace, std::vector<Rgba8>* image) {
    ProgramPlayer p(trace);
    try {
        p.play();
        if (image) *image = p.readImage();
    } catch (...) {
        p.release();
        throw;
    }
    p.release();
}

}  // namespace rg::conformance::detail

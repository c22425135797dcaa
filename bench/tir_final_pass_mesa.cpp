#include "tir_final_pass_mesa.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstddef>

#include "core/error.h"
#include "gl_program.h"

namespace rg::bench::tir_final_pass {

// ---- the GLSL twin ---------------------------------------------------------------------
//
// GLSL 1.30 (OpenGL 3.0, the GeForce 8800's generation) of EyeVP (demos/tir/tir_programs.h)
// and TirFP. The fragment shader mirrors demos/tir/tir_search.h, which is the definition:
// each function below is the one of the same name there or in the lane arithmetic it takes
// from rasterizer/quad_program_math.h, with its operations in the same order (dot products
// as (x·x + y·y) + z·z, normalize as v·(1/√(v·v)), min and max as GLSL defines them —
// min(x, y) = y < x ? y : x, the order of quad_program_math.h's min), the lane selects as
// branches, SearchConstants as the uniform struct k. What GLSL leaves to the
// implementation stays llvmpipe's: its compiler may rewrite a/b as a·(1/b) and 1/√x as
// one operation, it converts to and filters binary16 its own way, and it rasterizes a
// y-up window. Change tir_search.h and this together; tests/peer/test_tir_final_pass_mesa.cpp
// compares the frames.

// EyeVP: eye = view·position, n = view·normal (w = 0), clip (px·x, py·y, pz·z + pw, −z).
// GL's clip volume is −w ≤ z ≤ w where Direct3D's is 0 ≤ z ≤ w: z is passed as 2z − w, so
// that GL's window depth is our window depth (the near plane clips where ours does).
const char* const kVertexShader = R"(#version 130
uniform mat4 view;
uniform float px, py, pz, pw;
in vec3 position;
in vec3 normal;
out vec4 eyePosition;
out vec4 eyeNormal;
void main() {
    vec4 eye = view * vec4(position, 1.0);
    vec4 n = view * vec4(normal, 0.0);
    eyePosition = vec4(eye.xyz, 1.0);
    eyeNormal = vec4(n.xyz, 0.0);
    vec4 clip = vec4(eye.x * px, eye.y * py, eye.z * pz + pw, -eye.z);
    gl_Position = vec4(clip.xy, 2.0 * clip.z - clip.w, clip.w);
}
)";

const char* const kFragmentShader = R"(#version 130
struct SearchConstants {
    float px, py, pz, pw, invPx, invPy, far, invFar, eta, epsilon, cosMiss, minDistance2;
    int bounces, itersFirst, itersLater, itersNearby, frontAndBack, searchNearby;
    float eyeToWorld[9];
};
uniform SearchConstants k;
uniform sampler2D backMap, frontMap, nearbyMap;
uniform samplerCube envMap;
in vec4 eyePosition;
in vec4 eyeNormal;
out vec4 colour;

float dot3(vec3 a, vec3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
vec3 normalize3(vec3 v) {
    float inv = 1.0 / sqrt(dot3(v, v));
    return v * inv;
}
vec4 toClip(vec3 p) { return vec4(p.x * k.px, p.y * k.py, p.z * k.pz + k.pw, -p.z); }
vec4 toClipDirection(vec3 d) { return vec4(d.x * k.px, d.y * k.py, d.z * k.pz, -d.z); }

float frustumExit(vec4 s, vec4 d) {
    float t = 3.0e38;
    if (d.w + d.x < 0.0) t = min(t, -(s.w + s.x) / (d.w + d.x));
    if (d.w - d.x < 0.0) t = min(t, -(s.w - s.x) / (d.w - d.x));
    if (d.w + d.y < 0.0) t = min(t, -(s.w + s.y) / (d.w + d.y));
    if (d.w - d.y < 0.0) t = min(t, -(s.w - s.y) / (d.w - d.y));
    if (d.z < 0.0) t = min(t, -s.z / d.z);
    if (d.w - d.z < 0.0) t = min(t, -(s.w - s.z) / (d.w - d.z));
    return max(t, 0.0);
}

vec2 mapCoords(float x, float y, float w) {
    float inv = 1.0 / w;
    return vec2(0.5 + 0.5 * (x * inv), 0.5 - 0.5 * (y * inv));
}

vec3 unproject(vec2 uv, float d) {
    float w = d * k.far;
    float ndcX = uv.x * 2.0 - 1.0, ndcY = 1.0 - uv.y * 2.0;
    return vec3(ndcX * w * k.invPx, ndcY * w * k.invPy, -w);
}

struct Probe {
    vec2 uv;
    vec4 texel;
};

Probe binarySearch(sampler2D map, vec4 s, vec4 e, int iterations) {
    float lo = 0.0, hi = 1.0;
    bool away = e.w > s.w;
    Probe p = Probe(vec2(0.0), vec4(0.0, 0.0, 0.0, 1.0));
    for (int i = 0; i < iterations; ++i) {
        float mid = 0.5 * (lo + hi);
        float mx = s.x + (e.x - s.x) * mid, my = s.y + (e.y - s.y) * mid;
        float mw = s.w + (e.w - s.w) * mid;
        p.uv = mapCoords(mx, my, mw);
        p.texel = textureLod(map, p.uv, 0.0);
        float depth = mw * k.invFar;
        bool crossed = p.texel.w >= 1.0 || (away && depth > p.texel.w) || (depth < p.texel.w && !away);
        if (crossed) hi = mid; else lo = mid;
    }
    return p;
}

struct Candidate {
    vec3 point, value;
    float cosine;
    bool valid;
};

Candidate candidateOf(Probe p, vec3 origin, vec3 dir) {
    Candidate c;
    c.point = unproject(p.uv, p.texel.w);
    c.value = p.texel.xyz;
    vec3 to = c.point - origin;
    float len2 = dot3(to, to);
    c.cosine = dot3(to, dir) / sqrt(len2);
    c.valid = p.texel.w < 1.0 && len2 > k.minDistance2 && c.cosine >= k.cosMiss;
    return c;
}

vec3 refractOrReflect(vec3 d, vec3 n, float eta, out bool tir) {
    float cosI = -dot3(d, n);
    float q = 1.0 - (eta * eta) * (1.0 - cosI * cosI);
    tir = q < 0.0;
    if (tir) return d + n * (2.0 * cosI);
    return normalize3(d * eta + n * (eta * cosI - sqrt(max(q, 0.0))));
}

vec3 facing(vec3 n, vec3 d) { return dot3(n, d) > 0.0 ? n * -1.0 : n; }

vec3 eyeToWorld(vec3 d) {
    return vec3((d.x * k.eyeToWorld[0] + d.y * k.eyeToWorld[1]) + d.z * k.eyeToWorld[2],
                (d.x * k.eyeToWorld[3] + d.y * k.eyeToWorld[4]) + d.z * k.eyeToWorld[5],
                (d.x * k.eyeToWorld[6] + d.y * k.eyeToWorld[7]) + d.z * k.eyeToWorld[8]);
}

void main() {
    // traceInside: the refraction at the front fragment, then up to k.bounces segments.
    vec3 p = eyePosition.xyz;
    vec3 view = normalize3(p);
    bool tir;
    vec3 dir = refractOrReflect(view, facing(normalize3(eyeNormal.xyz), view), 1.0 / k.eta, tir);
    vec3 origin = p;
    bool inside = true;
    for (int b = 0; b < k.bounces; ++b) {
        if (!inside) break;
        int iterations = b == 0 ? k.itersFirst : k.itersLater;
        vec4 s = toClip(origin + dir * k.epsilon);
        vec4 d = toClipDirection(dir);
        float tEnd = frustumExit(s, d);
        vec4 e = vec4(s.x + d.x * tEnd, s.y + d.y * tEnd, s.z + d.z * tEnd, s.w + d.w * tEnd);
        Candidate back = candidateOf(binarySearch(backMap, s, e, iterations), origin, dir);
        Candidate hit = back;
        if (k.frontAndBack != 0) {
            Candidate front = candidateOf(binarySearch(frontMap, s, e, iterations), origin, dir);
            bool useFront = (front.valid && !back.valid) || (front.valid && front.cosine > back.cosine);
            if (useFront) {
                hit.point = front.point;
                hit.value = front.value;
            }
            hit.valid = back.valid || front.valid;
        }
        bool moved = hit.valid;  // inside here
        bool reflects;
        vec3 next = refractOrReflect(dir, facing(normalize3(hit.value), dir), k.eta, reflects);
        if (moved) {
            origin = hit.point;
            dir = next;
        }
        inside = moved && reflects;
    }
    // exitColor: the nearby map where the search finds it, else the environment.
    vec3 c = textureLod(envMap, eyeToWorld(dir), 0.0).rgb;
    if (k.searchNearby != 0) {
        vec4 s = toClip(origin + dir * k.epsilon);
        vec4 d = toClipDirection(dir);
        float tEnd = frustumExit(s, d);
        vec4 e = vec4(s.x + d.x * tEnd, s.y + d.y * tEnd, s.z + d.z * tEnd, s.w + d.w * tEnd);
        Candidate near = candidateOf(binarySearch(nearbyMap, s, e, k.itersNearby), origin, dir);
        if (near.valid) c = near.value;
    }
    colour = vec4(c, 1.0);
}
)";

namespace {

// A 2D or cube face image of RGBA16F texels given as floats (binary16 values: the
// conversion to GL_RGBA16F is exact).
void uploadMap(GLenum unit, const std::vector<glm::vec4>& texels) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glActiveTexture(unit);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA16F, kWidth, kHeight, 0, GL_RGBA, GL_FLOAT, texels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
}

}  // namespace

void setupGl(const Inputs& in, const char* fragment) {
    // An RGBA8 colour texture and a 24-bit depth renderbuffer, the formats of our side.
    gl::bindOffscreenTarget(kWidth, kHeight, /*depth=*/true, "tir_final_pass");
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    // Front faces only. A front face appears counter-clockwise on the screen in both APIs
    // (docs/hardware.md, "Orientation and culling"): ours culls the clockwise ones
    // (D3DCULL_CW), GL culls GL_BACK with GL_CCW front faces. The test's coverage check
    // (the same refractive pixels on both sides) would see the other faces drawn.
    glEnable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClearDepth(1.0);

    // Units 0–3 as TirFP's: back, front, nearby maps (rows from the top: v = 0 at the
    // first row uploaded, as mapCoords' v), the environment.
    uploadMap(GL_TEXTURE0, in.back);
    uploadMap(GL_TEXTURE1, in.front);
    uploadMap(GL_TEXTURE2, in.nearby);
    GLuint env = 0;
    glGenTextures(1, &env);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_CUBE_MAP, env);
    for (int f = 0; f < 6; ++f)  // GL's face order is ours: +X, −X, +Y, −Y, +Z, −Z
        glTexImage2D(GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), 0, GL_RGBA16F, in.envSize, in.envSize, 0,
                     GL_RGBA, GL_FLOAT, in.env[size_t(f)].data());
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAX_LEVEL, 0);
    glDisable(GL_TEXTURE_CUBE_MAP_SEAMLESS);  // ours filters each face on its own

    const GLuint program = gl::useProgram(kVertexShader, fragment, {"position", "normal"}, "tir_final_pass");

    // ---- uniforms: EyeVP's and SearchConstants' values ----
    auto at = [program](const char* name) { return glGetUniformLocation(program, name); };
    glUniformMatrix4fv(at("view"), 1, GL_FALSE, &in.vp.view[0][0]);  // glm is column-major too
    glUniform1f(at("px"), in.vp.px);
    glUniform1f(at("py"), in.vp.py);
    glUniform1f(at("pz"), in.vp.pz);
    glUniform1f(at("pw"), in.vp.pw);
    const tir::SearchConstants& k = in.k;
    const std::pair<const char*, float> floats[] = {
        {"k.px", k.px},       {"k.py", k.py},           {"k.pz", k.pz},
        {"k.pw", k.pw},       {"k.invPx", k.invPx},     {"k.invPy", k.invPy},
        {"k.far", k.far},     {"k.invFar", k.invFar},   {"k.eta", k.eta},
        {"k.epsilon", k.epsilon}, {"k.cosMiss", k.cosMiss}, {"k.minDistance2", k.minDistance2}};
    for (const auto& [name, v] : floats) glUniform1f(at(name), v);
    const std::pair<const char*, int32_t> ints[] = {
        {"k.bounces", k.bounces},         {"k.itersFirst", k.itersFirst},
        {"k.itersLater", k.itersLater},   {"k.itersNearby", k.itersNearby},
        {"k.frontAndBack", k.frontAndBack}, {"k.searchNearby", k.searchNearby}};
    for (const auto& [name, v] : ints) glUniform1i(at(name), v);
    glUniform1fv(at("k.eyeToWorld"), 9, k.eyeToWorld);
    glUniform1i(at("backMap"), tir::kUnitBack);
    glUniform1i(at("frontMap"), tir::kUnitFront);
    glUniform1i(at("nearbyMap"), tir::kUnitNearby);
    glUniform1i(at("envMap"), tir::kUnitEnv);

    // ---- the refractor: TirVertex records as they are, indices in an element buffer ----
    GLuint vao = 0, buffers[2] = {};
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(2, buffers);
    glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(in.vertices.size() * sizeof(tir::TirVertex)), in.vertices.data(),
                 GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(tir::TirVertex),
                          reinterpret_cast<const void*>(offsetof(tir::TirVertex, position)));
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(tir::TirVertex),
                          reinterpret_cast<const void*>(offsetof(tir::TirVertex, normal)));
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[1]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(in.indices.size() * sizeof(uint32_t)), in.indices.data(),
                 GL_STATIC_DRAW);

    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        throw Error("tir_final_pass: GL error " + std::to_string(e) + " in setup");
}

void drawFrameGl(const Inputs& in) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawElements(GL_TRIANGLES, GLsizei(in.indices.size()), GL_UNSIGNED_INT, nullptr);
}

MesaImage renderMesa(const Inputs& in, int threads, const std::string& fragment) {
    return renderMesaFrame("tir_final_pass", kWidth, kHeight, threads, RowOrder::TopRowFirst, [&] {
        setupGl(in, fragment.c_str());
        drawFrameGl(in);
    });
}

}  // namespace rg::bench::tir_final_pass

#include "impostor_peers_mesa.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstddef>
#include <utility>

#include "core/error.h"
#include "gl_program.h"

namespace rg::bench::impostor_peers {

// ---- the GLSL twins ------------------------------------------------------------------------
//
// GLSL 1.30 (OpenGL 3.0, the GeForce 8800's generation) of WorldVP
// (demos/impostors/impostor_programs.h), GlassFP<false, false> and GlassHeightFP<false,
// false> (impostor_height_programs.h). The fragment shaders mirror impostor_search.h,
// impostor_shading.h, impostor_height_search.h and impostor_height_shading.h, which are the
// definition: each function below is the one of the same name there (or in the lane
// arithmetic of rasterizer/quad_program_math.h), with its operations in the same order — dot
// products as (x·x + y·y) + z·z, normalize as v·(1/√(v·v)), min and max as the lane types
// define them (minL(x, y) = y < x ? y : x, maxL(x, y) = x < y ? y : x: max(0, NaN) is 0,
// which secantStep relies on), constants computed on the CPU as the programs compute them
// (1/η, the height map's 1/(sHi − sLo)), the lane selects and masks as branches on one
// fragment. A lane outside a search's mask reads nothing on ours; here it reads and ignores
// the texel, and its other values follow the same arithmetic. What GLSL leaves to the
// implementation stays llvmpipe's: its compiler may rewrite a/b as a·(1/b) and fuse
// multiply-adds, and it selects cube faces and snaps texel coordinates its own way. Change
// the demos' programs and these together; tests/peer/test_impostor_peers_mesa.cpp compares
// the frames.

// WorldVP: varyings the world position (w = 1) and normal (w = 0); clip = viewProj·position.
// GL's clip volume is −w ≤ z ≤ w where Direct3D's is 0 ≤ z ≤ w: z is passed as 2z − w, so
// that GL's window depth is our window depth.
const char* const kVertexShader = R"(#version 130
uniform mat4 viewProj;
in vec3 position;
in vec3 normal;
out vec4 worldPosition;
out vec4 worldNormal;
void main() {
    worldPosition = vec4(position, 1.0);
    worldNormal = vec4(normal, 0.0);
    vec4 clip = viewProj * vec4(position, 1.0);
    gl_Position = vec4(clip.xy, 2.0 * clip.z - clip.w, clip.w);
}
)";

namespace {

// The lane arithmetic, the object's constants and the secant search (impostor_search.h), the
// environment lookups and the combination (impostor_shading.h): both programs' part.
const char* const kCommon = R"(#version 130
// ObjectFrame (impostor_shading.h): the piece's; invEta = 1/η as the program computes it.
uniform vec3 eye;
uniform int iterations;
uniform vec3 centre;
uniform float toLocal[9];
uniform float eta, invEta, f0;
uniform vec3 absorption;
uniform samplerCube envMap;
in vec4 worldPosition;
in vec4 worldNormal;
out vec4 colour;

float minL(float a, float b) { return b < a ? b : a; }
float maxL(float a, float b) { return a < b ? b : a; }
float dot3(vec3 a, vec3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
float length3(vec3 v) { return sqrt(dot3(v, v)); }
vec3 normalize3(vec3 v) {
    float inv = 1.0 / sqrt(dot3(v, v));
    return v * inv;
}
vec3 facing(vec3 n, vec3 d) { return dot3(n, d) > 0.0 ? n * -1.0 : n; }
vec3 refractOrReflect(vec3 d, vec3 n, float e, out bool tir) {
    float cosI = -dot3(d, n);
    float k = 1.0 - (e * e) * (1.0 - cosI * cosI);
    tir = k < 0.0;
    vec3 t = normalize3(d * e + n * (e * cosI - sqrt(maxL(k, 0.0))));
    vec3 r = d + n * (2.0 * cosI);
    return tir ? r : t;
}
vec3 mul3(vec3 v) {
    return vec3((v.x * toLocal[0] + v.y * toLocal[1]) + v.z * toLocal[2],
                (v.x * toLocal[3] + v.y * toLocal[4]) + v.z * toLocal[5],
                (v.x * toLocal[6] + v.y * toLocal[7]) + v.z * toLocal[8]);
}
vec3 mulT3(vec3 v) {
    return vec3((v.x * toLocal[0] + v.y * toLocal[3]) + v.z * toLocal[6],
                (v.x * toLocal[1] + v.y * toLocal[4]) + v.z * toLocal[7],
                (v.x * toLocal[2] + v.y * toLocal[5]) + v.z * toLocal[8]);
}
vec3 reflect3(vec3 d, vec3 n) { return d + n * (2.0 * -dot3(d, n)); }
float fresnelSchlick(float cosI, float F0) {
    float m = 1.0 - minL(maxL(cosI, 0.0), 1.0);
    float m2 = m * m;
    return F0 + (1.0 - F0) * (m2 * m2 * m);
}
float expNeg(float z) {
    float w = minL(maxL(z, 0.0), 16.0) * 0.0625;
    float e = 1.0 - w * (1.0 - w * (0.5 - w * (0.16666667 - w * 0.041666668)));
    e = e * e;
    e = e * e;
    e = e * e;
    return e * e;
}

// ---- the secant search (impostor_search.h) ----
struct Search {
    vec3 point;
    float d;
    vec4 texel;
};
float distanceRatio(vec3 y, float stored) { return length3(y) / stored; }
float secantStep(float dU, float aU, float dO, float aO, float fallback) {
    float den = aO - aU;
    float d = dU + (dO - dU) * ((1.0 - aU) / den);
    return maxL(0.0, den != 0.0 ? d : fallback);
}
float stepTowardsInfinity(float dy, float ay, float rl) { return maxL(0.0, dy + rl * (1.0 - ay)); }

// The last undershoot (dU, aU) and overshoot (dO, aO) seen, after a point at d of ratio a.
void classify(float d, float a, bool seeded, inout bool hasUnder, inout bool hasOver, inout float dU,
              inout float aU, inout float dO, inout float aO) {
    bool under = a < 1.0;
    bool over = !under;
    if (seeded) over = over && !(hasUnder && d < dU);
    if (under) {
        dU = d;
        aU = a;
    }
    if (over) {
        dO = d;
        aO = a;
    }
    hasUnder = hasUnder || under;
    hasOver = hasOver || over;
}

Search secantSearch(samplerCube map, vec3 x, vec3 R, bool seeded) {
    float xR = dot3(x, R);
    bool hasUnder = false, hasOver = false;
    float dU = 0.0, aU = 0.0, dO = 0.0, aO = 0.0;
    if (seeded) {
        float dc = maxL(0.0, -xR);
        vec3 c = x + R * dc;
        float ac = distanceRatio(c, textureLod(map, c, 0.0).w);
        hasUnder = ac < 1.0;
        dU = dc;
        aU = ac;
    }
    // r: classical environment mapping's texel along R; p: the plane through r ⟂ R.
    float rl = textureLod(map, R, 0.0).w;
    float dp = maxL(0.0, rl - xR);
    vec3 p = x + R * dp;
    float ap = distanceRatio(p, textureLod(map, p, 0.0).w);
    classify(dp, ap, seeded, hasUnder, hasOver, dU, aU, dO, aO);
    // l: on the line through r and p'.
    float d = stepTowardsInfinity(dp, ap, rl);
    vec3 y = x + R * d;
    vec4 t = textureLod(map, y, 0.0);
    bool xRead = false;
    for (int i = 0; i < iterations; ++i) {
        classify(d, distanceRatio(y, t.w), seeded, hasUnder, hasOver, dU, aU, dO, aO);
        // No undershoot yet: x itself at its own ratio (read once).
        bool needX = !hasUnder && !xRead;
        if (needX) {
            float ax = distanceRatio(x, textureLod(map, x, 0.0).w);
            dU = 0.0;
            aU = ax;
            xRead = true;
        }
        d = hasOver ? secantStep(dU, aU, dO, aO, d) : stepTowardsInfinity(dU, aU, rl);
        y = x + R * d;
        t = textureLod(map, y, 0.0);
    }
    return Search(y, d, t);
}

struct EnvSample {
    vec3 colour;
    float d;
};
EnvSample envLookup(vec3 origin, vec3 dir) {
    Search s = secantSearch(envMap, origin - centre, dir, false);
    return EnvSample(s.texel.xyz, s.d);
}

struct Paths {
    vec3 reflOrigin, reflDir, exitOrigin, exitDir, transmit;
    float fresnel;
};
Paths exitPaths(vec3 P, vec3 Nraw, vec3 V);

void main() {
    vec3 P = worldPosition.xyz;
    vec3 V = normalize3(P - eye);
    Paths g = exitPaths(P, worldNormal.xyz, V);
    EnvSample er = envLookup(g.reflOrigin, g.reflDir);
    EnvSample et = envLookup(g.exitOrigin, g.exitDir);
    vec3 c = er.colour * g.fresnel + (et.colour * g.transmit) * (1.0 - g.fresnel);
    colour = vec4(c, 1.0);
}
)";

// tracePaths (impostor_shading.h): the exit by the secant search in the refractor distance
// map, seeded; under total internal reflection at the exit one more search.
const char* const kSecantExit = R"(
uniform samplerCube refractorMap;

Paths exitPaths(vec3 P, vec3 Nraw, vec3 V) {
    Paths g;
    vec3 N = facing(normalize3(Nraw), V);
    float cosI = -dot3(V, N);
    g.fresnel = fresnelSchlick(cosI, f0);
    g.reflOrigin = P;
    g.reflDir = reflect3(V, N);
    bool tirIn;
    vec3 T = refractOrReflect(V, N, invEta, tirIn);
    vec3 xl = mul3(P - centre), Tl = mul3(T);
    Search s = secantSearch(refractorMap, xl, Tl, true);
    vec3 Q = centre + mulT3(s.point);
    vec3 Nq = mulT3(normalize3(s.texel.xyz));
    bool tirOut;
    g.exitDir = refractOrReflect(T, facing(Nq, T), eta, tirOut);
    g.exitOrigin = Q;
    float len = s.d;
    if (tirOut) {
        Search s2 = secantSearch(refractorMap, mul3(Q - centre), mul3(g.exitDir), true);
        vec3 Q2 = centre + mulT3(s2.point);
        vec3 N2 = mulT3(normalize3(s2.texel.xyz));
        bool tir2;
        vec3 out2 = refractOrReflect(g.exitDir, facing(N2, g.exitDir), eta, tir2);
        g.exitOrigin = Q2;
        g.exitDir = out2;
        len = len + s2.d;
    }
    g.transmit = vec3(expNeg(absorption.x * len), expNeg(absorption.y * len), expNeg(absorption.z * len));
    return g;
}
)";

// tracePathsHeight (impostor_height_shading.h) with heightSearch and bisect
// (impostor_height_search.h): the billboard facing the ray's origin, Figure 7's segment, the
// binary search, the mirrored retry. HeightFrame's uScale = 1/(sHi − sLo), vScale =
// 1/(tHi − tLo) as the program computes them.
const char* const kHeightExit = R"(
uniform sampler2D heightMap;
uniform vec2 axis;
uniform float sLo, sHi, tLo, tHi, hMax, uScale, vScale;
uniform int steps;

struct Billboard {
    float wx, wz, bx, bz, ax, az;
};
Billboard billboardFacing(vec3 o) {
    Billboard bb;
    bb.ax = axis.x;
    bb.az = axis.y;
    float x = o.x - bb.ax, z = o.z - bb.az;
    float len2 = x * x + z * z;
    bool ok = len2 > 1e-12;
    float inv = 1.0 / sqrt(ok ? len2 : 1.0);
    bb.wx = ok ? x * inv : 0.0;
    bb.wz = ok ? z * inv : 1.0;
    bb.bx = bb.wz;
    bb.bz = 0.0 - bb.wx;
    return bb;
}

// One reading of the map at ray parameter d: whether the point is inside, and its texel.
bool readInside(vec3 o, vec3 r, float sigma, float d, bool live, out vec4 texel) {
    float s = o.x + r.x * d, t = o.y + r.y * d, h = (o.z + r.z * d) * sigma;
    texel = textureLod(heightMap, vec2((s - sLo) * uScale, (tHi - t) * vScale), 0.0);
    return live && h < texel.w;
}

struct Bisection {
    float a, b;
    bool found;
    vec4 insideTexel;
};
// An exit search: b moves to the midpoints outside, a to those inside.
Bisection bisect(vec3 o, vec3 r, float sigma, float a0, float b0, bool live) {
    Bisection bs;
    bs.a = a0;
    bs.b = b0;
    vec4 ta, tb;
    bool inB = readInside(o, r, sigma, b0, live, tb);
    readInside(o, r, sigma, a0, live, ta);
    bool bWanted = live && !inB;
    for (int i = 0; i < steps; ++i) {
        float m = 0.5 * (bs.a + bs.b);
        vec4 tm;
        bool inside = readInside(o, r, sigma, m, live, tm);
        bool wanted = live && !inside;
        if (wanted) {
            bs.b = m;
            tb = tm;
        } else {
            bs.a = m;
            ta = tm;
        }
        bWanted = bWanted || wanted;
    }
    bs.found = bWanted;
    bs.insideTexel = ta;
    return bs;
}

struct HeightHit {
    vec3 point, normal;
    float d;
    bool found;
};
HeightHit heightSearch(vec3 o, vec3 R, bool live) {
    HeightHit hit;
    Billboard bb = billboardFacing(o);
    float ox = o.x - bb.ax, oz = o.z - bb.az;
    vec3 os = vec3(ox * bb.bx + oz * bb.bz, o.y, ox * bb.wx + oz * bb.wz);
    vec3 rs = vec3(R.x * bb.bx + R.z * bb.bz, R.y, R.x * bb.wx + R.z * bb.wz);
    // rayBox (impostor_search.h) against s, t in the map's domain, |h| ≤ hMax.
    float ix = 1.0 / rs.x, iy = 1.0 / rs.y, iz = 1.0 / rs.z;
    float ax = (sLo - os.x) * ix, bx = (sHi - os.x) * ix;
    float ay = (tLo - os.y) * iy, by = (tHi - os.y) * iy;
    float az = (-hMax - os.z) * iz, bz = (hMax - os.z) * iz;
    float tNear = maxL(maxL(minL(ax, bx), minL(ay, by)), minL(az, bz));
    float tFar = minL(minL(maxL(ax, bx), maxL(ay, by)), maxL(az, bz));
    bool inBox = live && tFar >= maxL(tNear, 0.0);
    float dNear = maxL(tNear, 0.0), dFar = tFar;
    float dPlane = (0.0 - os.z) / rs.z;
    bool ahead = dPlane > 0.0;
    bool frontFirst = ahead && dPlane > dNear;
    bool case1 = frontFirst && dPlane < dFar;
    bool case3a = ahead && !frontFirst;
    float end1 = case1 ? dPlane : dFar;
    float sigma1 = case3a ? -1.0 : 1.0;
    Bisection first = bisect(os, rs, sigma1, dNear, end1, inBox);
    bool retry = inBox && case1 && !first.found;
    Bisection second = first;
    if (retry) second = bisect(os, rs, -1.0, dPlane, dFar, retry);
    float a = retry ? second.a : first.a, b = retry ? second.b : first.b;
    vec4 tex = retry ? second.insideTexel : first.insideTexel;
    float sigma = retry ? -1.0 : sigma1;
    hit.found = inBox && ((retry && second.found) || (first.found && !retry));
    hit.d = 0.5 * (a + b);
    hit.point = o + R * hit.d;
    float ns = tex.x, nt = tex.y, nh = tex.z * sigma;
    hit.normal = vec3(ns * bb.bx + nh * bb.wx, nt, ns * bb.bz + nh * bb.wz);
    return hit;
}

Paths exitPaths(vec3 P, vec3 Nraw, vec3 V) {
    Paths g;
    vec3 N = facing(normalize3(Nraw), V);
    float cosI = -dot3(V, N);
    g.fresnel = fresnelSchlick(cosI, f0);
    g.reflOrigin = P;
    g.reflDir = reflect3(V, N);
    bool tirIn;
    vec3 T = refractOrReflect(V, N, invEta, tirIn);
    vec3 xl = mul3(P - centre), Tl = mul3(T);
    HeightHit h = heightSearch(xl, Tl, true);
    vec3 Q = centre + mulT3(h.point);
    vec3 Nq = mulT3(normalize3(h.normal));
    bool tirOut;
    vec3 outDir = refractOrReflect(T, facing(Nq, T), eta, tirOut);
    tirOut = tirOut && h.found;
    g.exitDir = h.found ? outDir : T;
    g.exitOrigin = Q;
    float len = h.d;
    if (tirOut) {
        HeightHit h2 = heightSearch(h.point, mul3(g.exitDir), true);
        vec3 Q2 = centre + mulT3(h2.point);
        vec3 N2 = mulT3(normalize3(h2.normal));
        bool tir2;
        vec3 out2 = refractOrReflect(g.exitDir, facing(N2, g.exitDir), eta, tir2);
        g.exitOrigin = Q2;
        if (h2.found) g.exitDir = out2;
        len = len + h2.d;
    }
    g.transmit = vec3(expNeg(absorption.x * len), expNeg(absorption.y * len), expNeg(absorption.z * len));
    return g;
}
)";

void pointClamp(GLenum target) {
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_MAX_LEVEL, 0);
}

// A cube of RGBA16F texels given as floats (binary16 values: the conversion is exact).
GLuint uploadCube(const Cube& c) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_CUBE_MAP, t);
    for (int f = 0; f < 6; ++f)  // GL's face order is ours: +X, −X, +Y, −Y, +Z, −Z
        glTexImage2D(GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), 0, GL_RGBA16F, c.size, c.size, 0, GL_RGBA, GL_FLOAT,
                     c.faces[size_t(f)].data());
    pointClamp(GL_TEXTURE_CUBE_MAP);
    return t;
}

GLuint uploadHeight(const HeightMap& h) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, h.size, h.size, 0, GL_RGBA, GL_FLOAT, h.texels.data());
    pointClamp(GL_TEXTURE_2D);
    return t;
}

// What the frame needs of the setup: textures, uniform locations.
struct GlState {
    std::vector<GLuint> env, refractors, heights;
    GLint centre = -1, toLocal = -1, eta = -1, invEta = -1, f0 = -1, absorption = -1;
    GLint axis = -1, sLo = -1, sHi = -1, tLo = -1, tHi = -1, hMax = -1, uScale = -1, vScale = -1, steps = -1;
};
GlState gl;  // one context per process (the peer child)

}  // namespace

const std::string& fragmentShader(Exit e) {
    static const std::string secant = std::string(kCommon) + kSecantExit;
    static const std::string height = std::string(kCommon) + kHeightExit;
    return e == Exit::Height ? height : secant;
}

void setupGl(const Inputs& in, const std::string& fragment) {
    gl = GlState{};
    // An RGBA8 colour texture and a 24-bit depth renderbuffer, the formats of our side.
    gl::bindOffscreenTarget(kWidth, kHeight, /*depth=*/true, "impostor peers");
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    // Front faces only: counter-clockwise on the screen in both APIs (docs/hardware.md,
    // "Orientation and culling"); ours culls the clockwise ones (D3DCULL_CW).
    glEnable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClearDepth(1.0);
    glDisable(GL_TEXTURE_CUBE_MAP_SEAMLESS);  // ours reads each face on its own

    for (const Cube& c : in.env) gl.env.push_back(uploadCube(c));
    for (const Cube& c : in.refractors) gl.refractors.push_back(uploadCube(c));
    for (const HeightMap& h : in.heights) gl.heights.push_back(uploadHeight(h));

    const GLuint program = gl::useProgram(kVertexShader, fragment.c_str(), {"position", "normal"}, "impostor peers");

    // ---- uniforms: the frame's, then the locations of each piece's ----
    auto at = [program](const char* name) { return glGetUniformLocation(program, name); };
    glUniformMatrix4fv(at("viewProj"), 1, GL_FALSE, &in.viewProj[0][0]);  // glm is column-major too
    glUniform3f(at("eye"), in.eye[0], in.eye[1], in.eye[2]);
    glUniform1i(at("iterations"), in.iterations);
    glUniform1i(at("envMap"), impostors::kUnitEnv);
    gl.centre = at("centre");
    gl.toLocal = at("toLocal");
    gl.eta = at("eta");
    gl.invEta = at("invEta");
    gl.f0 = at("f0");
    gl.absorption = at("absorption");
    if (in.exit == Exit::Secant) {
        glUniform1i(at("refractorMap"), impostors::kUnitRefractor);
    } else {
        glUniform1i(at("heightMap"), impostors::kUnitHeight);
        gl.axis = at("axis");
        gl.sLo = at("sLo");
        gl.sHi = at("sHi");
        gl.tLo = at("tLo");
        gl.tHi = at("tHi");
        gl.hMax = at("hMax");
        gl.uScale = at("uScale");
        gl.vScale = at("vScale");
        gl.steps = at("steps");
    }

    // ---- the meshes: ImpostorVertex records as they are, indices per piece ----
    GLuint vao = 0, buffers[2] = {};
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(2, buffers);
    glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(in.vertices.size() * sizeof(impostors::ImpostorVertex)),
                 in.vertices.data(), GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(impostors::ImpostorVertex),
                          reinterpret_cast<const void*>(offsetof(impostors::ImpostorVertex, position)));
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(impostors::ImpostorVertex),
                          reinterpret_cast<const void*>(offsetof(impostors::ImpostorVertex, normal)));
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[1]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(in.indices.size() * sizeof(uint32_t)), in.indices.data(),
                 GL_STATIC_DRAW);

    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        throw Error("impostor peers: GL error " + std::to_string(e) + " in setup");
}

void drawFrameGl(const Inputs& in) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    for (const Draw& d : in.draws) {
        const impostors::ObjectFrame& o = d.frame;
        glActiveTexture(GL_TEXTURE0 + impostors::kUnitEnv);
        glBindTexture(GL_TEXTURE_CUBE_MAP, gl.env[size_t(d.env)]);
        glUniform3f(gl.centre, o.centre[0], o.centre[1], o.centre[2]);
        glUniform1fv(gl.toLocal, 9, o.toLocal);
        glUniform1f(gl.eta, o.eta);
        glUniform1f(gl.invEta, 1.0f / o.eta);
        glUniform1f(gl.f0, o.f0);
        glUniform3f(gl.absorption, o.absorption[0], o.absorption[1], o.absorption[2]);
        if (in.exit == Exit::Secant) {
            glActiveTexture(GL_TEXTURE0 + impostors::kUnitRefractor);
            glBindTexture(GL_TEXTURE_CUBE_MAP, gl.refractors[size_t(d.refractor)]);
        } else {
            const impostors::HeightFrame& h = in.heights[size_t(d.refractor)].frame;
            glActiveTexture(GL_TEXTURE0 + impostors::kUnitHeight);
            glBindTexture(GL_TEXTURE_2D, gl.heights[size_t(d.refractor)]);
            glUniform2f(gl.axis, h.axis[0], h.axis[1]);
            glUniform1f(gl.sLo, h.sLo);
            glUniform1f(gl.sHi, h.sHi);
            glUniform1f(gl.tLo, h.tLo);
            glUniform1f(gl.tHi, h.tHi);
            glUniform1f(gl.hMax, h.hMax);
            glUniform1f(gl.uScale, 1.0f / (h.sHi - h.sLo));
            glUniform1f(gl.vScale, 1.0f / (h.tHi - h.tLo));
            glUniform1i(gl.steps, h.steps);
        }
        glDrawElementsBaseVertex(GL_TRIANGLES, GLsizei(d.indexCount), GL_UNSIGNED_INT,
                                 reinterpret_cast<const void*>(size_t(d.firstIndex) * sizeof(uint32_t)),
                                 GLint(d.firstVertex));
    }
}

MesaImage renderMesa(const Inputs& in, int threads, const std::string& fragment) {
    const std::string& fs = fragment.empty() ? fragmentShader(in.exit) : fragment;
    return renderMesaFrame(workloadName(in.exit), kWidth, kHeight, threads, RowOrder::TopRowFirst, [&] {
        setupGl(in, fs);
        drawFrameGl(in);
    });
}

}  // namespace rg::bench::impostor_peers

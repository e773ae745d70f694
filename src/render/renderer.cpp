// The path tracer: Embree 3 for rays, oneTBB over rows. Unidirectional path tracing with next-
// event estimation and multiple importance sampling (power heuristic, Veach 1997), Russian
// roulette, and the feature buffers the denoisers need (docs/renderer.md).
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>

#include "render/bsdf.h"
#include "render/sampler.h"
#include "render/scene.h"
#include "rtd/error.h"

namespace rtd::render {

namespace {

constexpr float kSkyDepth = 1e4f;     // depth written where the primary ray escapes (as src/synthetic)
constexpr int kMaxMirrorChain = 8;    // mirror bounces followed for the reflection features
// Reflection features (reflected*, reflectedFootprint) are written below this roughness:
// Voorhuis' threshold for reflection motion vectors and the Eq. 6 bandwidth (Sec. 4.2).
constexpr float kReflectionFeatureRoughness = 0.4f;
constexpr float kOffscreen = -1e4f;   // previous position of points that were behind the camera

float powerHeuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0f;
}

/// Ray differentials with respect to the pixel coordinates x and y (Igehy 1999): of the
/// position on the ray and of its unit direction.
struct RayDifferential {
  V3 dPdx, dPdy, dDdx, dDdy;

  /// Igehy Eq. 2-3 (transfer): the ray P + t D hits a surface of normal n at distance t.
  void transfer(V3 d, float t, V3 n) {
    const float dn = dot(d, n);
    for (V3* dp : {&dPdx, &dPdy}) {
      const V3 moved = *dp + (dp == &dPdx ? dDdx : dDdy) * t;
      *dp = std::fabs(dn) > 1e-8f ? moved - d * (dot(moved, n) / dn) : moved;
    }
  }
  /// Igehy Eq. 15 (reflection): D' = D - 2 (D.N) N, with dN the normal's derivatives.
  void reflect(V3 d, V3 n, V3 dNdx, V3 dNdy) {
    const float dN = dot(d, n);
    dDdx = dDdx - (n * (dot(dDdx, n) + dot(d, dNdx)) + dNdx * dN) * 2.0f;
    dDdy = dDdy - (n * (dot(dDdy, n) + dot(d, dNdy)) + dNdy * dN) * 2.0f;
  }
  float footprint() const { return 0.5f * (length(dPdx) + length(dPdy)); }
};

/// One frame's geometry in world space: the Embree scene plus what shading needs.
struct FrameGeometry {
  RTCScene rtc = nullptr;
  std::vector<std::vector<V3>> positions, normals;  // per object, world space
  std::vector<M4> world, worldInverse;
  std::vector<float> emissionScale;  // per object: Object::emissionAt (light switches)
  // Emissive triangles (area lights): per light, its object and primitive; lightOffset[object]
  // is the index of the object's first triangle light (-1: not emissive).
  struct Light {
    int object;
    uint32_t prim;
    float area;
    V3 emission;
  };
  std::vector<Light> lights;
  std::vector<float> lightCdf;     // cumulative power, normalised to 1
  std::vector<float> lightProb;    // selection probability of each triangle (within triangles)
  std::vector<int> lightOffset;
  float pTriangles = 0, pSun = 0, pSky = 0;
  ~FrameGeometry() {
    if (rtc) rtcReleaseScene(rtc);
  }
};

struct Surface {
  V3 p, ng, ns;  // position, geometric and shading normal (both facing the incoming ray)
  V3 baseColor{0};
  V3 emission{0};
  float metallic = 0, roughness = 1, specular = 0.5f;
  float t = 0;
  int object = -1, material = -1;
  uint32_t prim = 0;
  bool frontFacing = true;
  bool pureMirror() const { return metallic >= 0.999f && roughness < kDeltaRoughness; }
};

/// Contributions of one sample, split as the native buffers want them.
struct Radiance {
  V3 total{0}, direct{0}, indirect{0}, diffuse{0}, specular{0};
  V3 indirectDiffuse{0};  // indirect and diffuse: Gersthofer's separately processed component
  V3 emission{0};  // emitted by the primary hit (or the sky seen directly), also in total
  float secondaryDistance = 0;
  void add(V3 c, bool direct_, bool specular_) {
    total += c;
    (direct_ ? direct : indirect) += c;
    (specular_ ? specular : diffuse) += c;
    if (!direct_ && !specular_) indirectDiffuse += c;
  }
  /// Light emitted towards the camera along a path that is the same in every sample (the
  /// primary hit's emission, or an emitter or the sky seen through perfect mirrors): counted,
  /// as Buffer::Emission documents, in Direct and Diffuse, whatever the mirrors it passed.
  void addEmission(V3 c) {
    add(c, true, false);
    emission += c;
  }
  void scale(float k) {
    total *= k, direct *= k, indirect *= k, diffuse *= k, specular *= k, indirectDiffuse *= k, emission *= k;
  }
};

}  // namespace

const char* eyeName(Eye eye) { return eye == Eye::Left ? "left" : eye == Eye::Right ? "right" : "center"; }

struct Renderer::Impl {
  std::shared_ptr<const SceneData> scene;
  RenderSettings settings;
  RTCDevice device = nullptr;
  RenderStats stats;
  std::mutex cacheMutex;
  std::map<int, std::shared_ptr<FrameGeometry>> geometryCache;

  ~Impl() {
    geometryCache.clear();
    if (device) rtcReleaseDevice(device);
  }

  // -------------------------------------------------------------------------------------------
  // Geometry

  std::shared_ptr<FrameGeometry> geometry(int index) {
    const int key = scene->anyAnimated() ? index : 0;
    std::lock_guard<std::mutex> lock(cacheMutex);
    if (auto it = geometryCache.find(key); it != geometryCache.end()) return it->second;
    auto g = build(float(key));
    if (geometryCache.size() >= 3) geometryCache.erase(geometryCache.begin());
    geometryCache[key] = g;
    return g;
  }

  std::shared_ptr<FrameGeometry> build(float t) {
    auto g = std::make_shared<FrameGeometry>();
    const size_t n = scene->objects.size();
    g->rtc = rtcNewScene(device);
    rtcSetSceneFlags(g->rtc, RTC_SCENE_FLAG_ROBUST);
    g->positions.resize(n);
    g->normals.resize(n);
    g->world.resize(n);
    g->worldInverse.resize(n);
    g->emissionScale.resize(n);
    g->lightOffset.assign(n, -1);
    V3 lo(1e30f), hi(-1e30f);
    for (size_t o = 0; o < n; ++o) {
      const Object& obj = scene->objects[o];
      const Mesh& mesh = scene->meshes[obj.mesh];
      g->world[o] = obj.worldAt(t);
      g->worldInverse[o] = inverse(g->world[o]);
      g->emissionScale[o] = obj.emissionAt(t);
      auto& P = g->positions[o];
      P.resize(mesh.positions.size());
      for (size_t i = 0; i < P.size(); ++i) {
        P[i] = g->world[o].point(mesh.positions[i]);
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], P[i][k]);
          hi[k] = std::max(hi[k], P[i][k]);
        }
      }
      if (!mesh.normals.empty()) {
        auto& N = g->normals[o];
        N.resize(mesh.normals.size());
        for (size_t i = 0; i < N.size(); ++i) N[i] = normalize(M4::normal(g->worldInverse[o], mesh.normals[i]));
      }
      RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                             3 * sizeof(float), P.size() + 1));  // +1: Embree reads 16 bytes
      for (size_t i = 0; i < P.size(); ++i) {
        vb[3 * i] = P[i].x;
        vb[3 * i + 1] = P[i].y;
        vb[3 * i + 2] = P[i].z;
      }
      const size_t tris = mesh.indices.size() / 3;
      auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                3 * sizeof(uint32_t), tris));
      std::copy(mesh.indices.begin(), mesh.indices.end(), ib);
      rtcCommitGeometry(geom);
      rtcAttachGeometryByID(g->rtc, geom, unsigned(o));
      rtcReleaseGeometry(geom);

      const Material& m = scene->materials[obj.material];
      if (m.isEmissive()) {
        // Lights are selected by their nominal power, whatever their switch (emissionScale): a
        // switched-off lamp keeps its share of the light samples (they find no radiance), so a
        // light switch does not reshuffle which light every other pixel's random numbers pick,
        // and re-shaded gradient samples lit by other lights keep their values.
        g->lightOffset[o] = int(g->lights.size());
        const V3 e = m.emissiveTexture >= 0 ? m.emissive * scene->textures[m.emissiveTexture].mean : m.emissive;
        for (size_t k = 0; k < tris; ++k) {
          const V3 a = P[mesh.indices[3 * k]], b = P[mesh.indices[3 * k + 1]], c = P[mesh.indices[3 * k + 2]];
          g->lights.push_back({int(o), uint32_t(k), 0.5f * length(cross(b - a, c - a)), e});
        }
      }
    }
    // Embree's commit turns on FTZ/DAZ on this thread while it builds, and a oneTBB arena
    // takes the floating-point mode of the thread that initializes it: run as the caller's
    // first oneTBB work, the build would initialize the caller's implicit arena in that mode,
    // and every later parallel loop of the application would run with FTZ/DAZ on its workers.
    // An arena of our own, initialized here in the caller's mode (and as wide as the caller's),
    // keeps the build's mode to the build (RendererSubnormal test).
    tbb::task_arena buildArena(tbb::this_task_arena::max_concurrency());
    buildArena.execute([&] { rtcCommitScene(g->rtc); });

    // Light selection: triangles by power (pi A L), the sun and the sky by the
    // power they send through the scene's bounding-sphere cross-section.
    double triPower = 0;
    g->lightCdf.resize(g->lights.size());
    g->lightProb.resize(g->lights.size());
    for (size_t i = 0; i < g->lights.size(); ++i) {
      triPower += kPi * g->lights[i].area * std::max(1e-6f, luminance(g->lights[i].emission));
    }
    double cumulative = 0;
    for (size_t i = 0; i < g->lights.size(); ++i) {
      const double p = kPi * g->lights[i].area * std::max(1e-6f, luminance(g->lights[i].emission)) / triPower;
      cumulative += p;
      g->lightProb[i] = float(p);
      g->lightCdf[i] = float(cumulative);
    }
    if (!g->lightCdf.empty()) g->lightCdf.back() = 1.0f;
    const float radius = lo.x <= hi.x ? 0.5f * length(hi - lo) : 1.0f;
    const float crossSection = kPi * radius * radius;
    const double sunPower = scene->sun.enabled() ? luminance(scene->sun.irradiance) * crossSection : 0.0;
    const Sky& sky = scene->sky;
    const double skyPower = sky.enabled()
        ? kPi * luminance((sky.zenith + sky.horizon + sky.ground * 2.0f) * 0.25f) * crossSection + 1e-6 : 0.0;
    const double total = triPower + sunPower + skyPower;
    if (total > 0) {
      g->pTriangles = float(triPower / total);
      g->pSun = float(sunPower / total);
      g->pSky = float(skyPower / total);
    }
    return g;
  }

  // -------------------------------------------------------------------------------------------
  // Rays

  static bool intersect(const FrameGeometry& g, V3 o, V3 d, float tmax, RTCRayHit& rh) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rh.ray.org_x = o.x;
    rh.ray.org_y = o.y;
    rh.ray.org_z = o.z;
    rh.ray.dir_x = d.x;
    rh.ray.dir_y = d.y;
    rh.ray.dir_z = d.z;
    rh.ray.tnear = 0;
    rh.ray.tfar = tmax;
    rh.ray.time = 0;
    rh.ray.mask = ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(g.rtc, &ctx, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }

  static bool occluded(const FrameGeometry& g, V3 o, V3 d, float tmax) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = o.x;
    r.org_y = o.y;
    r.org_z = o.z;
    r.dir_x = d.x;
    r.dir_y = d.y;
    r.dir_z = d.z;
    r.tnear = 0;
    r.tfar = tmax;
    r.time = 0;
    r.mask = ~0u;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(g.rtc, &ctx, &r);
    return r.tfar < 0;
  }

  /// Origin offset along the geometric normal against self-intersection, scaled with the
  /// coordinates' magnitude (float spacing grows with it).
  static V3 offsetOrigin(const Surface& s, V3 dir) {
    const float scale = 1e-4f * std::max(1.0f, std::max(std::fabs(s.p.x), std::max(std::fabs(s.p.y), std::fabs(s.p.z))));
    return s.p + s.ng * (dot(dir, s.ng) >= 0 ? scale : -scale);
  }

  Surface surface(const FrameGeometry& g, const RTCRayHit& rh, V3 dir) const {
    Surface s;
    s.object = int(rh.hit.geomID);
    s.prim = rh.hit.primID;
    s.t = rh.ray.tfar;
    const Object& obj = scene->objects[s.object];
    const Mesh& mesh = scene->meshes[obj.mesh];
    const Material& m = scene->materials[obj.material];
    s.material = obj.material;
    const uint32_t i0 = mesh.indices[3 * s.prim], i1 = mesh.indices[3 * s.prim + 1], i2 = mesh.indices[3 * s.prim + 2];
    const float u = rh.hit.u, v = rh.hit.v, w = 1.0f - u - v;
    const auto& P = g.positions[s.object];
    s.p = P[i0] * w + P[i1] * u + P[i2] * v;
    V3 ng = normalize(cross(P[i1] - P[i0], P[i2] - P[i0]));
    V3 ns = ng;
    if (mesh.analyticSphere) {
      const V3 local = g.worldInverse[s.object].point(s.p);
      ns = normalize(M4::normal(g.worldInverse[s.object], local));
    } else if (!g.normals[s.object].empty()) {
      const auto& N = g.normals[s.object];
      ns = normalize(N[i0] * w + N[i1] * u + N[i2] * v);
    }
    float tu = 0, tv = 0;
    const bool hasUv = !mesh.uvs.empty();
    if (hasUv) {
      tu = mesh.uvs[2 * i0] * w + mesh.uvs[2 * i1] * u + mesh.uvs[2 * i2] * v;
      tv = mesh.uvs[2 * i0 + 1] * w + mesh.uvs[2 * i1 + 1] * u + mesh.uvs[2 * i2 + 1] * v;
    }
    if (hasUv && m.normalTexture >= 0) {
      // Tangent frame from the triangle's uv parameterisation.
      const V3 e1 = P[i1] - P[i0], e2 = P[i2] - P[i0];
      const float du1 = mesh.uvs[2 * i1] - mesh.uvs[2 * i0], dv1 = mesh.uvs[2 * i1 + 1] - mesh.uvs[2 * i0 + 1];
      const float du2 = mesh.uvs[2 * i2] - mesh.uvs[2 * i0], dv2 = mesh.uvs[2 * i2 + 1] - mesh.uvs[2 * i0 + 1];
      const float det = du1 * dv2 - du2 * dv1;
      if (std::fabs(det) > 1e-12f) {
        V3 tangent = (e1 * dv2 - e2 * dv1) / det;
        tangent = normalize(tangent - ns * dot(ns, tangent));
        const V3 bitangent = cross(ns, tangent) * (det < 0 ? -1.0f : 1.0f);
        const V3 tn = scene->textures[m.normalTexture].sample(tu, tv) * 2.0f - V3(1.0f);
        ns = normalize(tangent * (tn.x * m.normalScale) + bitangent * (tn.y * m.normalScale) + ns * tn.z);
      }
    }
    // Emitters emit from their front face only (counter-clockwise winding, as glTF).
    s.frontFacing = dot(ng, dir) < 0;
    // Two-sided scattering: both normals face the incoming ray.
    if (dot(ng, dir) > 0) {
      ng = -ng;
      ns = -ns;
    }
    if (dot(ns, dir) >= 0) ns = ng;  // shading normal facing away from the viewer: fall back
    s.ng = ng;
    s.ns = ns;
    s.baseColor = m.baseColor;
    if (hasUv && m.baseColorTexture >= 0) s.baseColor = s.baseColor * scene->textures[m.baseColorTexture].sample(tu, tv);
    s.metallic = m.metallic;
    s.roughness = m.roughness;
    if (hasUv && m.metallicRoughnessTexture >= 0) {
      const V3 mr = scene->textures[m.metallicRoughnessTexture].sample(tu, tv);  // glTF: G roughness, B metal
      s.roughness *= mr.y;
      s.metallic *= mr.z;
    }
    s.specular = m.specular;
    s.emission = s.frontFacing ? m.emissive * g.emissionScale[s.object] : V3(0);
    if (s.frontFacing && hasUv && m.emissiveTexture >= 0) s.emission = s.emission * scene->textures[m.emissiveTexture].sample(tu, tv);
    return s;
  }

  /// The shading normal (without normal maps, unflipped) of surface s's primitive at a point
  /// q near s.p, for the normal's derivatives along a ray differential.
  V3 shadingNormalAt(const FrameGeometry& g, const Surface& s, V3 q) const {
    const Object& obj = scene->objects[s.object];
    const Mesh& mesh = scene->meshes[obj.mesh];
    const uint32_t i0 = mesh.indices[3 * s.prim], i1 = mesh.indices[3 * s.prim + 1], i2 = mesh.indices[3 * s.prim + 2];
    const auto& P = g.positions[s.object];
    if (mesh.analyticSphere) return normalize(M4::normal(g.worldInverse[s.object], g.worldInverse[s.object].point(q)));
    if (g.normals[s.object].empty()) return normalize(cross(P[i1] - P[i0], P[i2] - P[i0]));
    const V3 e1 = P[i1] - P[i0], e2 = P[i2] - P[i0], r = q - P[i0];
    const float d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2), d20 = dot(r, e1), d21 = dot(r, e2);
    const float den = d00 * d11 - d01 * d01;
    if (std::fabs(den) < 1e-20f) return s.ns;
    const float u = (d11 * d20 - d01 * d21) / den, v = (d00 * d21 - d01 * d20) / den;
    const auto& N = g.normals[s.object];
    return normalize(N[i0] * (1.0f - u - v) + N[i1] * u + N[i2] * v);
  }

  /// Derivatives of s's shading normal (as stored in s, facing the ray) along dP, by a
  /// central difference of shadingNormalAt over a step of ~1e-3 of the surface's scale.
  V3 normalDerivative(const FrameGeometry& g, const Surface& s, V3 dP) const {
    const float len = length(dP);
    if (len <= 0) return V3(0);
    const float h = 1e-3f * std::max(1.0f, length(s.p)) / len;
    const V3 a = shadingNormalAt(g, s, s.p + dP * h), b = shadingNormalAt(g, s, s.p - dP * h);
    const float sign = dot(shadingNormalAt(g, s, s.p), s.ns) < 0 ? -1.0f : 1.0f;
    return (a - b) * (sign * 0.5f / h);
  }

  // -------------------------------------------------------------------------------------------
  // Lights

  struct LightSample {
    V3 wi, radiance{0};
    float pdf = 0, distance = 1e30f;
    bool delta = false;
  };

  float sunSolidAngle() const {
    const float a = scene->sun.angleDegrees * kPi / 180.0f;
    return 2.0f * kPi * (1.0f - std::cos(a));
  }

  bool sampleLight(const FrameGeometry& g, const Surface& s, float uSel, float u1, float u2, LightSample& ls) const {
    if (uSel < g.pTriangles) {
      const float u = uSel / g.pTriangles;
      const size_t i = std::min(size_t(std::lower_bound(g.lightCdf.begin(), g.lightCdf.end(), u) - g.lightCdf.begin()),
                                g.lights.size() - 1);
      const auto& L = g.lights[i];
      const Mesh& mesh = scene->meshes[scene->objects[L.object].mesh];
      const auto& P = g.positions[L.object];
      const V3 a = P[mesh.indices[3 * L.prim]], b = P[mesh.indices[3 * L.prim + 1]], c = P[mesh.indices[3 * L.prim + 2]];
      const float su = std::sqrt(u1), b0 = 1.0f - su, b1 = u2 * su;
      const V3 q = a * b0 + b * b1 + c * (1.0f - b0 - b1);
      V3 d = q - s.p;
      const float dist2 = dot(d, d);
      if (dist2 <= 0) return false;
      ls.distance = std::sqrt(dist2);
      ls.wi = d / ls.distance;
      const V3 nl = normalize(cross(b - a, c - a));
      const float cosL = -dot(nl, ls.wi);  // front face only
      if (cosL <= 1e-6f || L.area <= 0) return false;
      ls.pdf = g.pTriangles * g.lightProb[i] * dist2 / (cosL * L.area);
      const Material& m = scene->materials[scene->objects[L.object].material];
      ls.radiance = m.emissive * g.emissionScale[L.object];
      if (m.emissiveTexture >= 0 && !mesh.uvs.empty()) {
        const uint32_t i0 = mesh.indices[3 * L.prim], i1 = mesh.indices[3 * L.prim + 1], i2 = mesh.indices[3 * L.prim + 2];
        const float tu = mesh.uvs[2 * i0] * b0 + mesh.uvs[2 * i1] * b1 + mesh.uvs[2 * i2] * (1 - b0 - b1);
        const float tv = mesh.uvs[2 * i0 + 1] * b0 + mesh.uvs[2 * i1 + 1] * b1 + mesh.uvs[2 * i2 + 1] * (1 - b0 - b1);
        ls.radiance = ls.radiance * scene->textures[m.emissiveTexture].sample(tu, tv);
      }
      ls.distance *= 0.999f;  // stop short of the light itself in the shadow ray
      return true;
    }
    if (uSel < g.pTriangles + g.pSun) {
      const Sun& sun = scene->sun;
      if (sun.angleDegrees <= 0) {
        ls.wi = sun.direction;
        ls.radiance = sun.irradiance;  // delta light: f cos E / p
        ls.pdf = g.pSun;
        ls.delta = true;
        return true;
      }
      const float cosMax = std::cos(sun.angleDegrees * kPi / 180.0f);
      const float cosT = 1.0f - u1 * (1.0f - cosMax), sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
      const float phi = 2.0f * kPi * u2;
      V3 t, b;
      basis(sun.direction, t, b);
      ls.wi = normalize(t * (sinT * std::cos(phi)) + b * (sinT * std::sin(phi)) + sun.direction * cosT);
      const float omega = sunSolidAngle();
      ls.radiance = sun.irradiance / omega;
      ls.pdf = g.pSun / omega;
      return true;
    }
    if (g.pSky <= 0) return false;
    // Sky: cosine-weighted around the shading normal.
    const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
    V3 t, b;
    basis(s.ns, t, b);
    ls.wi = t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + s.ns * std::sqrt(std::max(0.0f, 1.0f - u1));
    const float c = dot(ls.wi, s.ns);
    if (c <= 1e-6f) return false;
    ls.pdf = g.pSky * c * kInvPi;
    ls.radiance = scene->sky.radiance(ls.wi);
    return true;
  }

  /// Pdf of sampleLight() choosing direction wi towards emissive triangle `light` at q.
  float trianglePdf(const FrameGeometry& g, int light, V3 from, const Surface& hit) const {
    const auto& L = g.lights[light];
    const V3 d = hit.p - from;
    const float dist2 = dot(d, d), cosL = std::fabs(dot(hit.ng, normalize(d)));
    if (cosL <= 1e-6f || L.area <= 0) return 0;
    return g.pTriangles * g.lightProb[light] * dist2 / (cosL * L.area);
  }

  /// Radiance arriving from an escaped ray, MIS-weighted against light sampling unless the
  /// previous bounce was a delta (or the camera).
  V3 escaped(const FrameGeometry& g, V3 dir, V3 prevNormal, float bsdfPdf, bool countFully) const {
    V3 result{0};
    const Sky& sky = scene->sky;
    if (sky.enabled()) {
      float w = 1.0f;
      if (!countFully) {
        const float c = dot(dir, prevNormal);
        w = powerHeuristic(bsdfPdf, c > 0 ? g.pSky * c * kInvPi : 0.0f);
      }
      result += sky.radiance(dir) * w;
    }
    const Sun& sun = scene->sun;
    if (sun.enabled() && sun.angleDegrees > 0 && dot(dir, sun.direction) >= std::cos(sun.angleDegrees * kPi / 180.0f)) {
      const float omega = sunSolidAngle();
      const float w = countFully ? 1.0f : powerHeuristic(bsdfPdf, g.pSun / omega);
      result += sun.irradiance / omega * w;
    }
    return result;
  }

  // -------------------------------------------------------------------------------------------
  // Path tracing

  /// One path from a primary hit (or miss). `primary` is the first surface hit, if any.
  Radiance tracePath(const FrameGeometry& g, V3 origin, V3 dir, const Surface* primary, Sampler& sampler,
                     uint64_t& rays) const {
    Radiance out;
    if (!primary) {
      out.addEmission(escaped(g, dir, V3(0), 0, true));
      return out;
    }
    Surface s = *primary;
    V3 throughput(1.0f), wo = -dir;
    bool firstSpecular = false, prevDelta = true;
    // Whether the path so far is the camera ray and perfect mirrors only, with no Russian
    // roulette: then the light emitted at the current vertex reaches the pixel the same way
    // in every sample (Buffer::Emission, noise-free), whether the vertex is the primary hit
    // or an emitter (or the sky) seen in a mirror.
    bool mirrorChain = true;
    float prevPdf = 0;
    V3 prevNormal = V3(0), prevPos = origin;
    const int maxDepth = settings.maxDepth;
    for (int bounce = 0;; ++bounce) {
      // Emission at this vertex (bounce = scattering events before it).
      if (s.emission.x > 0 || s.emission.y > 0 || s.emission.z > 0) {
        float w = 1.0f;
        if (!prevDelta) {
          const int li = g.lightOffset[s.object];
          const float pl = li >= 0 ? trianglePdf(g, li + int(s.prim), prevPos, s) : 0.0f;
          w = powerHeuristic(prevPdf, pl);
        }
        if (mirrorChain) out.addEmission(throughput * s.emission);  // w = 1: no light sampling so far
        else out.add(throughput * s.emission * w, bounce <= 1, firstSpecular);
      }
      if (bounce >= maxDepth) break;
      const auto [uSel, uRR] = sampler.next2D();
      const auto [ul1, ul2] = sampler.next2D();
      const auto [uLobe, unused] = sampler.next2D();
      const auto [ub1, ub2] = sampler.next2D();
      (void)unused;
      const Bsdf bsdf(s.ns, wo, s.baseColor, s.metallic, s.roughness, s.specular);

      // Next-event estimation (not for pure mirrors: a light sample never hits a delta lobe).
      if (!bsdf.pureSpecular()) {
        LightSample ls;
        if (sampleLight(g, s, uSel, ul1, ul2, ls) && dot(ls.wi, s.ng) > 0) {
          const Bsdf::Eval e = bsdf.eval(wo, ls.wi);
          const V3 f = e.diffuse + e.specular;
          if (maxComponent(f) > 0) {
            ++rays;
            if (!occluded(g, offsetOrigin(s, ls.wi), ls.wi, ls.distance)) {
              const float w = ls.delta ? 1.0f : powerHeuristic(ls.pdf, e.pdf);
              const V3 scale = throughput * ls.radiance * (w / ls.pdf);
              if (bounce == 0) {
                out.add(scale * e.diffuse, true, false);
                out.add(scale * e.specular, true, true);
              } else {
                out.add(scale * f, false, firstSpecular);
              }
            }
          }
        }
      }

      // Continue the path by sampling the BSDF.
      const Bsdf::Sample bs = bsdf.sample(wo, uLobe, ub1, ub2);
      if (!bs.valid || dot(bs.wi, s.ng) <= 0) break;
      if (bounce == 0) firstSpecular = bs.specular;
      throughput *= bs.weight;
      mirrorChain = mirrorChain && bsdf.pureSpecular();
      if (bounce + 1 >= settings.russianRouletteDepth) {
        const float q = std::min(0.95f, maxComponent(throughput));
        if (uRR >= q) break;
        throughput = throughput / q;
        mirrorChain = false;
      }
      prevDelta = bs.delta;
      prevPdf = bs.pdf;
      prevNormal = s.ns;
      prevPos = s.p;
      const V3 o = offsetOrigin(s, bs.wi);
      RTCRayHit rh;
      ++rays;
      if (!intersect(g, o, bs.wi, 1e30f, rh)) {
        if (bounce == 0) out.secondaryDistance = 0;
        const V3 sky = throughput * escaped(g, bs.wi, prevNormal, prevPdf, prevDelta);
        if (mirrorChain) out.addEmission(sky);
        else out.add(sky, bounce == 0, firstSpecular);
        break;
      }
      s = surface(g, rh, bs.wi);
      if (bounce == 0) out.secondaryDistance = length(s.p - prevPos);
      wo = -bs.wi;
    }
    return out;
  }

  // -------------------------------------------------------------------------------------------
  // Camera

  View view(int index, Eye eye) const {
    return scene->viewAt(float(index), float(settings.width) / float(settings.height), eye, settings.eyeDistance);
  }

  static V3 pixelDirection(const View& v, float px, float py, int w, int h) {
    const float sx = (2.0f * px / float(w) - 1.0f) * v.tanHalfFovY * v.aspect;
    const float sy = (1.0f - 2.0f * py / float(h)) * v.tanHalfFovY;
    return normalize(v.forward + v.right * sx + v.up * sy);
  }

  uint32_t pixelSeed(int index, int x, int y, Eye eye, uint32_t salt) const {
    uint32_t h = hashCombine(settings.seed ^ salt, uint32_t(index));
    h = hashCombine(h, uint32_t(eye));
    h = hashCombine(h, uint32_t(y) * 65537u + uint32_t(x));
    return h & (kSeedLimit - 1);
  }

  bool hidden(int x, int y, Eye eye) const {
    if (!settings.hiddenArea) return false;
    const float u = (float(x) + 0.5f) / float(settings.width) * 2.0f - 1.0f;
    const float v = (float(y) + 0.5f) / float(settings.height) * 2.0f - 1.0f;  // down
    if (u * u + v * v > 1.18f) return true;  // outside the lens circle, radius sqrt(1.18)
    // The nose: the inner bottom corner of each eye (the right side of the left eye).
    const float inner = eye == Eye::Left ? u : eye == Eye::Right ? -u : -2.0f;
    return inner > 0.75f && v > 0.55f;
  }

  bool masked(int index, int x, int y, Eye eye) const {
    if (settings.sampleFraction >= 1.0f) return true;
    constexpr int N = kBlueNoiseSize * kBlueNoiseSize;
    const int count = std::max(1, int(std::lround(double(settings.sampleFraction) * N)));
    // Rotate through the rank map: frame k traces ranks [k*count, (k+1)*count) modulo N, so with
    // sampleFraction = 1/m every pixel is traced exactly once every m frames (Gersthofer Sec.
    // 3.3.1: the thresholded masks, cycled). The right eye runs half the rank range (N/2) ahead,
    // so for sampleFraction <= 1/2 the two eyes' masks of a frame are disjoint (with 1/m, m even,
    // the right eye traces mask k + m/2 while the left traces mask k).
    const int64_t eyeShift = eye == Eye::Right ? N / 2 : 0;
    const int offset = int((int64_t(index) * count + eyeShift) % N);
    const int rank = blueNoiseRanks()[(y % kBlueNoiseSize) * kBlueNoiseSize + (x % kBlueNoiseSize)];
    return (rank - offset + N) % N < count;
  }

  /// Samples of pixel (x, y) for `seed` averaged (what render() writes to `color`).
  /// `primaryDir`: the primary ray's direction when it is not the pixel centre's (a gradient
  /// sample forward-projected to a point between pixel centres); its hit is `centreHit`.
  Radiance shade(const FrameGeometry& g, const View& v, int x, int y, uint32_t seed, int spp, int sampleBase,
                 const Surface* centreHit, uint64_t& rays, const V3* primaryDir = nullptr) const {
    Radiance sum;
    for (int k = 0; k < spp; ++k) {
      Sampler sampler(seed, uint32_t(sampleBase + k));
      const auto [jx, jy] = sampler.next2D();
      Radiance r;
      if (settings.pixelJitter || !centreHit) {
        const float px = settings.pixelJitter ? float(x) + jx : float(x) + 0.5f;
        const float py = settings.pixelJitter ? float(y) + jy : float(y) + 0.5f;
        const V3 d = pixelDirection(v, px, py, settings.width, settings.height);
        RTCRayHit rh;
        ++rays;
        if (intersect(g, v.eye, d, 1e30f, rh)) {
          const Surface s = surface(g, rh, d);
          r = tracePath(g, v.eye, d, &s, sampler, rays);
        } else {
          r = tracePath(g, v.eye, d, nullptr, sampler, rays);
        }
      } else {
        const V3 d = primaryDir ? *primaryDir : pixelDirection(v, float(x) + 0.5f, float(y) + 0.5f, settings.width,
                                                                settings.height);
        r = tracePath(g, v.eye, d, centreHit->object >= 0 ? centreHit : nullptr, sampler, rays);
      }
      clampSample(r);
      sum.total += r.total;
      sum.direct += r.direct;
      sum.indirect += r.indirect;
      sum.diffuse += r.diffuse;
      sum.specular += r.specular;
      sum.indirectDiffuse += r.indirectDiffuse;
      sum.emission += r.emission;
      if (k == 0) sum.secondaryDistance = r.secondaryDistance;
    }
    sum.scale(1.0f / float(spp));
    return sum;
  }

  /// Samples per pixel of `color`: one (the guide ray) with guide-ray supersampling.
  int colorSpp() const { return settings.guideRays ? 1 : settings.spp; }

  /// Non-guide sample k of pixel (x, y) (guide-ray supersampling, Voorhuis Sec. 5): jittered
  /// inside the pixel with the k-th sample's random numbers, as shade() jitters; `offset` is
  /// its position minus the pixel centre, `depth` / `normal` its primary hit's (sky: kSkyDepth, 0).
  Radiance jitteredSample(const FrameGeometry& g, const View& v, int x, int y, uint32_t seed, int k, float offset[2],
                          float& depth, V3& normal, uint64_t& rays) const {
    Sampler sampler(seed, uint32_t(k));
    const auto [jx, jy] = sampler.next2D();
    offset[0] = jx - 0.5f;
    offset[1] = jy - 0.5f;
    const V3 d = pixelDirection(v, float(x) + jx, float(y) + jy, settings.width, settings.height);
    RTCRayHit rh;
    ++rays;
    Radiance r;
    depth = kSkyDepth;
    normal = V3(0);
    if (intersect(g, v.eye, d, 1e30f, rh)) {
      const Surface s = surface(g, rh, d);
      depth = dot(s.p - v.eye, v.forward);
      normal = s.ns;
      r = tracePath(g, v.eye, d, &s, sampler, rays);
    } else {
      r = tracePath(g, v.eye, d, nullptr, sampler, rays);
    }
    clampSample(r);
    return r;
  }

  void clampSample(Radiance& r) const {
    if (settings.clampLuminance <= 0) return;
    const float l = luminance(r.total);
    if (l > settings.clampLuminance) {
      r.scale(settings.clampLuminance / l);
    }
  }

  /// Pixel coordinates of world point p seen by view v (perspective), or nullopt behind it.
  static bool project(const View& v, V3 p, float& px, float& py, int w, int h) {
    const V3 c = p - v.eye;
    const float z = dot(c, v.forward);
    if (z <= 1e-6f) return false;
    const float sx = dot(c, v.right) / z / (v.tanHalfFovY * v.aspect), sy = dot(c, v.up) / z / v.tanHalfFovY;
    px = (sx * 0.5f + 0.5f) * float(w);
    py = (0.5f - sy * 0.5f) * float(h);
    return true;
  }

  // -------------------------------------------------------------------------------------------
  // A-SVGF gradient samples (Schied et al. 2018; docs/renderer.md "Gradient samples")

  /// What forward projection needs of one pixel's sample: its seed, luminance and primary hit.
  struct PrimarySample {
    uint32_t seed = 0;
    float luminance = 0;
    int object = -1;  // -1: no primary hit (sky)
    uint32_t prim = 0;
    float u = 0, v = 0, t = 0;
    bool traced = false;  // false: skipped by the sparse mask (no sample to re-shade)
  };
  /// A frame's gradient-sample candidates: per 3x3 stratum the traced pixel of maximum luminance
  /// (with a primary hit), and the frame's view and object transforms.
  struct GradientSource {
    int index = -1;
    struct Candidate {
      int x, y;
      PrimarySample sample;
    };
    std::vector<Candidate> candidates;
    View view;
    std::vector<M4> world;
  };
  std::map<Eye, GradientSource> gradientSources;  // of the last frame rendered, per eye

  static constexpr int kStratum = 3;

  GradientSource selectCandidates(int index, const View& v, const FrameGeometry& g,
                                  const std::vector<PrimarySample>& samples) const {
    const int w = settings.width, h = settings.height;
    GradientSource src;
    src.index = index;
    src.view = v;
    src.world = g.world;
    const int sw = (w + kStratum - 1) / kStratum, sh = (h + kStratum - 1) / kStratum;
    for (int sy = 0; sy < sh; ++sy)
      for (int sx = 0; sx < sw; ++sx) {
        int usable[kStratum * kStratum], count = 0, best = -1;
        for (int y = sy * kStratum; y < std::min(h, (sy + 1) * kStratum); ++y)
          for (int x = sx * kStratum; x < std::min(w, (sx + 1) * kStratum); ++x) {
            const int i = y * w + x;
            if (samples[i].object < 0 || !samples[i].traced) continue;
            usable[count++] = i;
            if (best < 0 || samples[i].luminance > samples[best].luminance) best = i;
          }
        if (best < 0) continue;
        // All black: any pixel tells whether light arrives now (Q2RTX picks one at random).
        if (!(samples[best].luminance > 0))
          best = usable[hashCombine(hashCombine(settings.seed, uint32_t(index)), uint32_t(sy * sw + sx)) % uint32_t(count)];
        src.candidates.push_back({best % w, best / w, samples[best]});
      }
    return src;
  }

  /// Forward-projects the candidates of frame index - 1 into frame `index`, re-shades the one
  /// that wins each current stratum with its old seed at its moved surface point, and writes
  /// the gradient-sample buffers.
  void writeGradientSamples(const GradientSource& src, const FrameGeometry& g, const View& v,
                            const std::vector<PrimarySample>& current, Frame& f, uint64_t& rayTotal) const {
    const int w = settings.width, h = settings.height;
    const int sw = (w + kStratum - 1) / kStratum;
    const bool sameView = std::memcmp(&v, &src.view, sizeof(View)) == 0;
    struct Projected {
      int stratum = -1, x = 0, y = 0;
      V3 dir;
      RTCRayHit hit;
    };
    std::vector<Projected> proj(src.candidates.size());
    std::atomic<uint64_t> rayCount{0};
    tbb::parallel_for(size_t(0), src.candidates.size(), [&](size_t k) {
      const auto& c = src.candidates[k];
      const PrimarySample& ps = c.sample;
      const int o = ps.object;
      if (o >= int(g.world.size())) return;
      Projected p{};
      RTCRayHit& rh = p.hit;
      rh.hit.geomID = unsigned(o);
      rh.hit.primID = ps.prim;
      rh.hit.u = ps.u;
      rh.hit.v = ps.v;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      if (sameView && std::memcmp(&src.world[o], &g.world[o], sizeof(M4)) == 0) {
        // Neither the camera nor the object moved: the projection is the identity, computed
        // exactly (the same ray and hit as the previous frame's sample).
        p.x = c.x;
        p.y = c.y;
        p.dir = pixelDirection(v, float(c.x) + 0.5f, float(c.y) + 0.5f, w, h);
        rh.ray.tfar = ps.t;
      } else {
        // The same triangle and barycentrics under this frame's object transform.
        const Mesh& mesh = scene->meshes[scene->objects[o].mesh];
        const auto& P = g.positions[o];
        const V3 q = P[mesh.indices[3 * ps.prim]] * (1.0f - ps.u - ps.v) + P[mesh.indices[3 * ps.prim + 1]] * ps.u +
                     P[mesh.indices[3 * ps.prim + 2]] * ps.v;
        float px, py;
        if (!project(v, q, px, py, w, h) || !(px >= 0 && py >= 0 && px < float(w) && py < float(h))) return;
        p.x = std::min(w - 1, int(px));
        p.y = std::min(h - 1, int(py));
        const V3 d = q - v.eye;
        const float t = length(d);
        p.dir = d / t;
        // Visible from the new viewpoint? (A disoccluded or newly hidden point has no sample.)
        RTCRayHit first;
        rayCount += 1;
        if (!intersect(g, v.eye, p.dir, 1e30f, first) || first.ray.tfar < t * (1.0f - 1e-3f)) return;
        rh.ray.tfar = t;
      }
      // The pixel it lands on must see the same object, so its features describe the sample.
      if (current[size_t(p.y) * w + p.x].object != o) return;
      p.stratum = (p.y / kStratum) * sw + p.x / kStratum;
      proj[k] = p;
    });
    // One sample per current stratum: the brightest previous sample landing there (then the
    // first in scan order), deterministic whatever the scheduling.
    std::vector<int> winner(size_t(sw) * ((h + kStratum - 1) / kStratum), -1);
    for (size_t k = 0; k < proj.size(); ++k) {
      const int st = proj[k].stratum;
      if (st < 0) continue;
      const int cur = winner[st];
      if (cur < 0 || src.candidates[k].sample.luminance > src.candidates[cur].sample.luminance) winner[st] = int(k);
    }
    tbb::parallel_for(size_t(0), winner.size(), [&](size_t st) {
      const int k = winner[st];
      if (k < 0) return;
      const Projected& p = proj[k];
      uint64_t rays = 0;
      const Surface s = surface(g, p.hit, p.dir);
      const Radiance r = shade(g, v, p.x, p.y, src.candidates[k].sample.seed, colorSpp(), 0, &s, rays, &p.dir);
      f[Buffer::GradientSample].at(p.x, p.y) = 1.0f;
      f[Buffer::GradientPrevious].at(p.x, p.y) = src.candidates[k].sample.luminance;
      f[Buffer::GradientCurrent].at(p.x, p.y) = luminance(r.total);
      rayCount += rays;
    });
    rayTotal += rayCount;
  }

  /// The gradient source of frame `index`: the cached one, or rendered again (random access).
  const GradientSource& gradientSource(int index, Eye eye) {
    auto it = gradientSources.find(eye);
    if (it == gradientSources.end() || it->second.index != index) {
      render(index, eye, false);
      it = gradientSources.find(eye);
    }
    return it->second;
  }

  Frame render(int index, Eye eye, bool withGradients = true, GuideRaySamples* guideSamples = nullptr) {
    const auto start = std::chrono::steady_clock::now();
    if (index < 0) throw Error("render: frame index " + std::to_string(index) + " is negative");
    const int w = settings.width, h = settings.height;
    const bool gradients = settings.allBuffers && settings.gradientSamples && !settings.pixelJitter;
    // The previous frame's candidates first (it may render that frame: it must not overwrite
    // this frame's statistics or geometry).
    const GradientSource* source = gradients && withGradients && index > 0 ? &gradientSource(index - 1, eye) : nullptr;
    const auto geomPtr = geometry(index);
    const FrameGeometry& g = *geomPtr;
    const int prevIndex = std::max(0, index - 1);
    const View v = view(index, eye), pv = view(prevIndex, eye);
    // Previous object transforms for object motion (static scenes share one geometry).
    std::vector<M4> prevWorld(scene->objects.size());
    for (size_t o = 0; o < prevWorld.size(); ++o) prevWorld[o] = scene->objects[o].worldAt(float(prevIndex));

    Frame f;
    f.number = index + 1;
    f.width = w;
    f.height = h;
    std::vector<Buffer> list = {Buffer::Color, Buffer::Albedo, Buffer::Normal, Buffer::Depth, Buffer::Position,
                                Buffer::Motion, Buffer::ObjectId, Buffer::MaterialId, Buffer::Roughness,
                                Buffer::Metalness, Buffer::DepthGradient, Buffer::Emission};
    if (settings.allBuffers)
      for (Buffer b : {Buffer::Direct, Buffer::Indirect, Buffer::Diffuse, Buffer::Specular, Buffer::ReflectedPosition,
                       Buffer::ReflectedNormal, Buffer::ReflectedAlbedo, Buffer::SecondaryDistance,
                       Buffer::MirrorDirection, Buffer::ReflectedFootprint, Buffer::Seed, Buffer::SampleMask,
                       Buffer::IndirectDiffuse})
        list.push_back(b);
    if (gradients)
      for (Buffer b : {Buffer::GradientSample, Buffer::GradientPrevious, Buffer::GradientCurrent}) list.push_back(b);
    if (settings.hiddenArea) list.push_back(Buffer::HiddenArea);
    for (Buffer b : list) f[b] = Image(w, h, bufferChannelCount(b));
    const bool all = settings.allBuffers;
    auto put3 = [&](Buffer b, int x, int y, V3 c) {
      float* p = f[b].pixel(x, y);
      p[0] = c.x, p[1] = c.y, p[2] = c.z;
    };
    std::vector<PrimarySample> samples(gradients ? size_t(w) * h : 0);
    if (guideSamples) {
      if (!settings.guideRays) throw Error("render: guide-ray samples asked for without RenderSettings::guideRays");
      const int n = std::max(0, settings.spp - 1);
      guideSamples->samples.assign(size_t(n), Frame{});
      guideSamples->offsets.assign(size_t(n), Image(w, h, 2));
      for (Frame& sf : guideSamples->samples) {
        sf.number = index + 1;
        sf.width = w;
        sf.height = h;
        for (Buffer b : {Buffer::Color, Buffer::Emission, Buffer::Depth, Buffer::Normal}) sf[b] = Image(w, h, bufferChannelCount(b));
        if (all)
          for (Buffer b : {Buffer::Direct, Buffer::Indirect, Buffer::Diffuse, Buffer::Specular, Buffer::IndirectDiffuse})
            sf[b] = Image(w, h, bufferChannelCount(b));
      }
    }

    std::atomic<uint64_t> rayCount{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 1), [&](const tbb::blocked_range<int>& range) {
      uint64_t rays = 0;
      for (int y = range.begin(); y != range.end(); ++y)
        for (int x = 0; x < w; ++x) {
          if (hidden(x, y, eye)) {  // the lens hides it: no ray, no shading (the stencil prepass)
            f[Buffer::HiddenArea].at(x, y) = 1.0f;
            continue;
          }
          const V3 d = pixelDirection(v, float(x) + 0.5f, float(y) + 0.5f, w, h);
          RTCRayHit rh;
          ++rays;
          Surface s;
          const bool hit = intersect(g, v.eye, d, 1e30f, rh);
          if (hit) s = surface(g, rh, d);
          const uint32_t seed = pixelSeed(index, x, y, eye, 0);
          const bool traced = masked(index, x, y, eye);
          Radiance r;
          if (traced) r = shade(g, v, x, y, seed, colorSpp(), 0, &s, rays);
          if (guideSamples)
            for (int k = 1; k < settings.spp; ++k) {
              Frame& sf = guideSamples->samples[size_t(k - 1)];
              float depth;
              V3 n;
              const Radiance sr = jitteredSample(g, v, x, y, seed, k, guideSamples->offsets[size_t(k - 1)].pixel(x, y), depth, n, rays);
              for (auto [b, c] : {std::pair{Buffer::Color, sr.total}, {Buffer::Emission, sr.emission}}) {
                float* p = sf[b].pixel(x, y);
                p[0] = c.x, p[1] = c.y, p[2] = c.z;
              }
              if (all)
                for (auto [b, c] : {std::pair{Buffer::Direct, sr.direct}, {Buffer::Indirect, sr.indirect},
                                    {Buffer::Diffuse, sr.diffuse}, {Buffer::Specular, sr.specular},
                                    {Buffer::IndirectDiffuse, sr.indirectDiffuse}}) {
                  float* p = sf[b].pixel(x, y);
                  p[0] = c.x, p[1] = c.y, p[2] = c.z;
                }
              sf[Buffer::Depth].at(x, y) = depth;
              float* pn = sf[Buffer::Normal].pixel(x, y);
              pn[0] = n.x, pn[1] = n.y, pn[2] = n.z;
            }
          put3(Buffer::Color, x, y, r.total);
          put3(Buffer::Emission, x, y, r.emission);
          if (all) {
            put3(Buffer::Direct, x, y, r.direct);
            put3(Buffer::Indirect, x, y, r.indirect);
            put3(Buffer::Diffuse, x, y, r.diffuse);
            put3(Buffer::Specular, x, y, r.specular);
            put3(Buffer::IndirectDiffuse, x, y, r.indirectDiffuse);
            f[Buffer::Seed].at(x, y) = float(seed);
            f[Buffer::SampleMask].at(x, y) = traced ? 1.0f : 0.0f;
            f[Buffer::SecondaryDistance].at(x, y) = r.secondaryDistance;
          }
          if (gradients && hit) {
            // Untraced pixels (sparse sampling) have no sample to re-shade; their hit still
            // tells whether a projected sample lands on the same object.
            samples[size_t(y) * w + x] = {seed,     luminance(r.total), int(rh.hit.geomID), rh.hit.primID,
                                          rh.hit.u, rh.hit.v,           rh.ray.tfar,         traced};
          }
          writeFeatures(g, v, pv, prevWorld, f, x, y, d, hit ? &s : nullptr, all, rays);
        }
      rayCount += rays;
    });
    uint64_t rays = rayCount;
    if (source) writeGradientSamples(*source, g, v, samples, f, rays);
    if (gradients) gradientSources[eye] = selectCandidates(index, v, g, samples);  // for the next frame

    f.camera.worldToCamera = v.worldToCamera().m;
    f.camera.projection = v.projection().m;
    f.camera.valid = true;
    stats = RenderStats{};
    stats.rays = rays;
    stats.samplesPerPixel = settings.spp;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return f;
  }

  void writeFeatures(const FrameGeometry& g, const View& v, const View& pv, const std::vector<M4>& prevWorld, Frame& f,
                     int x, int y, V3 d, const Surface* s, bool all, uint64_t& rays) const {
    const int w = settings.width, h = settings.height;
    auto put3 = [&](Buffer b, V3 c) {
      float* p = f[b].pixel(x, y);
      p[0] = c.x, p[1] = c.y, p[2] = c.z;
    };
    if (!s) {
      f[Buffer::Depth].at(x, y) = kSkyDepth;
      // Background: motion of a direction at infinity (camera rotation only).
      float px, py;
      const View rotOnly{pv.eye, pv.right, pv.up, pv.forward, pv.tanHalfFovY, pv.aspect};
      if (project(rotOnly, rotOnly.eye + d, px, py, w, h)) {
        f[Buffer::Motion].at(x, y, 0) = px - (float(x) + 0.5f);
        f[Buffer::Motion].at(x, y, 1) = py - (float(y) + 0.5f);
      } else {
        f[Buffer::Motion].at(x, y, 0) = kOffscreen - float(x);
        f[Buffer::Motion].at(x, y, 1) = kOffscreen - float(y);
      }
      if (all) put3(Buffer::ReflectedAlbedo, V3(0));
      return;
    }
    put3(Buffer::Albedo, s->baseColor);
    put3(Buffer::Normal, s->ns);
    put3(Buffer::Position, s->p);
    const float depth = dot(s->p - v.eye, v.forward);
    f[Buffer::Depth].at(x, y) = depth;
    f[Buffer::ObjectId].at(x, y) = float(s->object + 1);
    f[Buffer::MaterialId].at(x, y) = float(s->material + 1);
    f[Buffer::Roughness].at(x, y) = s->roughness;
    f[Buffer::Metalness].at(x, y) = s->metallic;
    // Depth gradient: depth of the hit's tangent plane through the next pixel's centre (right,
    // down), minus this depth: exact for planes, no leaking across silhouettes.
    for (int axis = 0; axis < 2; ++axis) {
      const V3 dn = pixelDirection(v, float(x) + 0.5f + (axis == 0), float(y) + 0.5f + (axis == 1), w, h);
      const float denom = dot(dn, s->ng);
      float grad = 0;
      if (std::fabs(denom) > 1e-6f) {
        const float t = dot(s->p - v.eye, s->ng) / denom;
        if (t > 0) grad = dot(dn * t, v.forward) - depth;
      }
      f[Buffer::DepthGradient].at(x, y, axis) = grad;
    }
    // Motion: the hit's object-space point under the previous object and camera transforms.
    const V3 local = g.worldInverse[s->object].point(s->p);
    const V3 prevP = prevWorld[s->object].point(local);
    float px, py;
    if (project(pv, prevP, px, py, w, h)) {
      f[Buffer::Motion].at(x, y, 0) = px - (float(x) + 0.5f);
      f[Buffer::Motion].at(x, y, 1) = py - (float(y) + 0.5f);
    } else {
      f[Buffer::Motion].at(x, y, 0) = kOffscreen - float(x);
      f[Buffer::Motion].at(x, y, 1) = kOffscreen - float(y);
    }
    if (!all) return;
    const V3 mirrorDir = reflect(d, s->ns);
    put3(Buffer::MirrorDirection, mirrorDir);
    if (!(s->roughness < kReflectionFeatureRoughness)) return;
    // Reflection features: follow the perfect mirror ray (the representative ray of a glossy
    // pixel) through any pure mirrors to the first non-mirror hit, carrying the ray
    // differentials of the pixel (Igehy 1999) for Voorhuis' Eq. 6 footprint.
    RayDifferential rd;
    {
      const float tx = 2.0f / float(w) * v.tanHalfFovY * v.aspect, ty = -2.0f / float(h) * v.tanHalfFovY;
      const V3 D = v.forward + v.right * ((2.0f * (float(x) + 0.5f) / float(w) - 1.0f) * v.tanHalfFovY * v.aspect) +
                   v.up * ((1.0f - 2.0f * (float(y) + 0.5f) / float(h)) * v.tanHalfFovY);
      const float l = length(D);
      auto unitDerivative = [&](V3 dD) { return (dD * (l * l) - D * dot(D, dD)) / (l * l * l); };
      rd.dPdx = rd.dPdy = V3(0);
      rd.dDdx = unitDerivative(v.right * tx);
      rd.dDdy = unitDerivative(v.up * ty);
    }
    rd.transfer(d, s->t, s->ng);
    rd.reflect(d, s->ns, normalDerivative(g, *s, rd.dPdx), normalDerivative(g, *s, rd.dPdy));
    const bool mirror = s->pureMirror();
    Surface cur = *s;
    V3 dir = mirrorDir;
    for (int k = 0; k < kMaxMirrorChain; ++k) {
      RTCRayHit rh;
      ++rays;
      if (!intersect(g, offsetOrigin(cur, dir), dir, 1e30f, rh)) {
        put3(Buffer::ReflectedAlbedo, V3(1.0f));  // sky seen in the mirror: nothing to demodulate
        if (k == 0 && mirror) f[Buffer::SecondaryDistance].at(x, y) = 0;
        return;
      }
      const Surface next = surface(g, rh, dir);
      rd.transfer(dir, next.t, next.ng);
      if (k == 0 && mirror) f[Buffer::SecondaryDistance].at(x, y) = length(next.p - cur.p);
      if (!next.pureMirror() || k + 1 == kMaxMirrorChain) {
        put3(Buffer::ReflectedPosition, next.p);
        put3(Buffer::ReflectedNormal, next.ns);
        put3(Buffer::ReflectedAlbedo, next.baseColor);
        f[Buffer::ReflectedFootprint].at(x, y) = rd.footprint();
        return;
      }
      rd.reflect(dir, next.ns, normalDerivative(g, next, rd.dPdx), normalDerivative(g, next, rd.dPdy));
      dir = reflect(dir, next.ns);
      cur = next;
    }
  }

  Image renderReference(int index, int spp, double budget, Eye eye) {
    const auto start = std::chrono::steady_clock::now();
    if (spp < 1) throw Error("reference: spp must be >= 1 (got " + std::to_string(spp) + ")");
    const int w = settings.width, h = settings.height;
    const auto geomPtr = geometry(index);
    const FrameGeometry& g = *geomPtr;
    const View v = view(index, eye);
    std::vector<double> sum(size_t(w) * h * 3, 0.0);
    std::vector<Surface> hits(size_t(w) * h);
    std::atomic<uint64_t> rayCount{0};
    // Centre hits once (the samples go through the pixel centre unless jitter is on).
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 1), [&](const tbb::blocked_range<int>& range) {
      uint64_t rays = 0;
      for (int y = range.begin(); y != range.end(); ++y)
        for (int x = 0; x < w; ++x) {
          if (hidden(x, y, eye)) continue;
          const V3 d = pixelDirection(v, float(x) + 0.5f, float(y) + 0.5f, w, h);
          RTCRayHit rh;
          ++rays;
          if (intersect(g, v.eye, d, 1e30f, rh)) hits[size_t(y) * w + x] = surface(g, rh, d);
        }
      rayCount += rays;
    });
    // Progressive passes of doubling size; the time budget is checked between passes.
    int done = 0;
    for (int batch = 1; done < spp; batch *= 2) {
      const int n = std::min(batch, spp - done);
      tbb::parallel_for(tbb::blocked_range<int>(0, h, 1), [&](const tbb::blocked_range<int>& range) {
        uint64_t rays = 0;
        for (int y = range.begin(); y != range.end(); ++y)
          for (int x = 0; x < w; ++x) {
            if (hidden(x, y, eye)) continue;  // never displayed: 0
            const uint32_t seed = pixelSeed(index, x, y, eye, 0x7e5f0a11u);
            const Surface& s = hits[size_t(y) * w + x];
            const Radiance r = shade(g, v, x, y, seed, n, done, &s, rays);
            double* p = &sum[(size_t(y) * w + x) * 3];
            p[0] += double(r.total.x) * n;
            p[1] += double(r.total.y) * n;
            p[2] += double(r.total.z) * n;
          }
        rayCount += rays;
      });
      done += n;
      if (budget > 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > budget) break;
    }
    Image img(w, h, 3);
    for (size_t i = 0; i < sum.size(); ++i) img.pixels[i] = float(sum[i] / done);
    stats = RenderStats{};
    stats.rays = rayCount;
    stats.samplesPerPixel = done;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return img;
  }
};

static void validate(const RenderSettings& s) {
  auto bad = [](const char* field, const std::string& what) {
    throw Error(std::string("render setting '") + field + "': " + what);
  };
  if (s.width < 1 || s.height < 1 || s.width > 16384 || s.height > 16384)
    bad("size", "must be between 1x1 and 16384x16384 (got " + std::to_string(s.width) + "x" + std::to_string(s.height) + ")");
  if (s.spp < 1) bad("spp", "must be >= 1 (got " + std::to_string(s.spp) + ")");
  if (s.maxDepth < 1) bad("maxDepth", "must be >= 1 (got " + std::to_string(s.maxDepth) + ")");
  if (s.russianRouletteDepth < 1) bad("russianRouletteDepth", "must be >= 1");
  if (!(s.sampleFraction > 0.0f && s.sampleFraction <= 1.0f)) bad("sampleFraction", "must be in (0, 1]");
  if (!(s.eyeDistance >= 0.0f) || !std::isfinite(s.eyeDistance)) bad("eyeDistance", "must be >= 0");
  if (!(s.clampLuminance >= 0.0f)) bad("clampLuminance", "must be >= 0");
  if (s.guideRays && (s.pixelJitter || s.sampleFraction < 1.0f))
    bad("guideRays", "needs unjittered guide rays at every pixel (no pixelJitter, sampleFraction 1)");
}

Renderer::Renderer(std::shared_ptr<const Scene> scene, RenderSettings settings) : impl_(std::make_unique<Impl>()) {
  auto data = std::dynamic_pointer_cast<const SceneData>(scene);
  if (!data) throw Error("render: the scene was not created by rtd::render::Scene::load");
  validate(settings);
  impl_->scene = data;
  impl_->settings = settings;
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw Error("render: cannot create the Embree device (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
}

Renderer::~Renderer() = default;
const RenderSettings& Renderer::settings() const { return impl_->settings; }
const RenderStats& Renderer::stats() const { return impl_->stats; }
Frame Renderer::render(int index, Eye eye) { return impl_->render(index, eye); }
Frame Renderer::render(int index, Eye eye, GuideRaySamples& samples) { return impl_->render(index, eye, true, &samples); }
Image Renderer::renderReference(int index, int spp, double secondsBudget, Eye eye) {
  return impl_->renderReference(index, spp, secondsBudget, eye);
}
uint32_t Renderer::pixelSeed(int index, int x, int y, Eye eye) const { return impl_->pixelSeed(index, x, y, eye, 0); }
bool Renderer::sampleMask(int index, int x, int y, Eye eye) const { return impl_->masked(index, x, y, eye); }
bool Renderer::hidden(int x, int y, Eye eye) const { return impl_->hidden(x, y, eye); }

std::array<float, 3> Renderer::shadePixel(int index, int x, int y, uint32_t seed, Eye eye) {
  const auto& s = impl_->settings;
  if (x < 0 || y < 0 || x >= s.width || y >= s.height)
    throw Error("shadePixel: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the image");
  if (seed >= kSeedLimit) throw Error("shadePixel: seed " + std::to_string(seed) + " exceeds 24 bits");
  const auto geom = impl_->geometry(index);
  const View v = impl_->view(index, eye);
  const V3 d = Impl::pixelDirection(v, float(x) + 0.5f, float(y) + 0.5f, s.width, s.height);
  RTCRayHit rh;
  Surface hit;
  if (Impl::intersect(*geom, v.eye, d, 1e30f, rh)) hit = impl_->surface(*geom, rh, d);
  uint64_t rays = 1;
  const auto r = impl_->shade(*geom, v, x, y, seed, impl_->colorSpp(), 0, &hit, rays);
  return {r.total.x, r.total.y, r.total.z};
}

// ---------------------------------------------------------------------------------------------
// Reference cache

std::filesystem::path ReferenceCache::defaultDir() {
  if (const char* d = std::getenv("RTD_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return std::filesystem::path(d) / "rtdenoise" / "references";
  if (const char* d = std::getenv("HOME"); d && *d) return std::filesystem::path(d) / ".cache" / "rtdenoise" / "references";
  return std::filesystem::temp_directory_path() / "rtdenoise-references";
}

std::filesystem::path ReferenceCache::entry(const Scene& scene, const RenderSettings& s, int index, int spp, Eye eye,
                                            double budgetSeconds) const {
  // Everything that changes the reference's pixels; not spp of the noisy input, not the mask.
  const std::string key = scene.contentHash() + "|" + std::to_string(s.width) + "x" + std::to_string(s.height) + "|d" +
                          std::to_string(s.maxDepth) + "|rr" + std::to_string(s.russianRouletteDepth) + "|s" +
                          std::to_string(s.seed) + "|j" + std::to_string(int(s.pixelJitter)) + "|e" + eyeName(eye) +
                          "|ed" + std::to_string(s.eyeDistance) + "|f" + std::to_string(index) + "|spp" +
                          std::to_string(spp) + "|b" + std::to_string(budgetSeconds) + "|v1" +
                          (s.hiddenArea ? "|hidden" : "");
  return dir / (scene.name() + "_" + hashHex(key) + ".exr");
}

Image ReferenceCache::fetchOrRender(Renderer& r, const Scene& scene, int index, int spp, double budgetSeconds, Eye eye,
                                    bool* cached) const {
  const std::filesystem::path file = dir.empty() ? std::filesystem::path() : entry(scene, r.settings(), index, spp, eye, budgetSeconds);
  if (cached) *cached = false;
  if (!file.empty() && std::filesystem::exists(file)) {
    try {
      Image img = readRgbExr(file);
      if (img.width == r.settings().width && img.height == r.settings().height) {
        if (cached) *cached = true;
        return img;
      }
    } catch (const Error&) {
      // A damaged entry is rendered again below and overwritten.
    }
  }
  Image img = r.renderReference(index, spp, budgetSeconds, eye);
  if (!file.empty()) {
    std::filesystem::create_directories(file.parent_path());
    writeRgbExr(file, img);
  }
  return img;
}

}  // namespace rtd::render

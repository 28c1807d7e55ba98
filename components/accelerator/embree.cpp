// accelerator "embree" — Intel Embree 3 BVHs: the default, and the fast path.
//
// Triangle meshes become Embree triangle geometry; analytic shapes (spheres, disks)
// become user geometry that calls back into IShape::intersect. Batches of rays (the
// wavefront renderers') are traced as packets of the CPU's width (rtcIntersect8/16, rtcOccluded8/16),
// as Embree streams (rtcIntersect1M) or one ray at a time, by the `batch` parameter;
// bench/RESULTS.md has what each gives per ray kind (packets are the default).
// Parameters: robust (bool) — Embree's robust mode, which never misses hits on edges and
// vertices, at about 20 % of ray speed. On by default, unlike Mitsuba 3: without it the
// conformance suite finds misses on edges (4 % of its edge rays) and a mirror's image
// loses 0.4 % of its light through cracks (tests/test_mirror_render.cpp); batch (packet |
// packet8 | packet16 | stream | single): packet is 16 wide where the CPU has AVX-512, else 8;
// bvh (two-level | flat): one BVH per shape under a top-level BVH over the shapes (Embree's
// two-level builder, which scene build quality "low" selects; each shape's BVH is built at
// Embree's default geometry quality, "medium": SAH), or one BVH over every triangle of the
// scene (quality "high": SAH with spatial splits; what Mitsuba 3 builds). Two-level is the
// default by measurement: +20 % samples/s on the Cornell box, +18 % on the glossy one; on a
// 10^7-triangle mesh as fast to trace, up to 9 % longer to load (bench/RESULTS.md,
// 2026-11-29). The likely reason: in a scene of a few large shapes (walls, boxes, a light)
// a flat BVH's leaves mix triangles of different walls under boxes as large as the room,
// while per-shape BVHs keep each wall in its own tight box.
// Reference: Wald et al. 2014, "Embree: A Kernel Framework for Efficient CPU Ray Tracing",
// ACM TOG 33(4).
#include "effigi/core/log.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <embree3/rtcore.h>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace effigi {
namespace {

void onEmbreeError(void*, RTCError code, const char* msg) {
    if (code != RTC_ERROR_NONE) log::warn("embree: {} (code {})", msg ? msg : "", int(code));
}

void userBounds(const RTCBoundsFunctionArguments* args) {
    BBox3f b = static_cast<const IShape*>(args->geometryUserPtr)->bbox();
    *args->bounds_o = RTCBounds{b.min.x, b.min.y, b.min.z, 0.f, b.max.x, b.max.y, b.max.z, 0.f};
}

Ray lane(RTCRayN* ray, unsigned N, unsigned i) {
    return Ray{{RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i)},
               {RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i)},
               RTCRayN_tfar(ray, N, i), RTCRayN_time(ray, N, i)};
}

void userIntersect(const RTCIntersectFunctionNArguments* args) {
    const auto* shape = static_cast<const IShape*>(args->geometryUserPtr);
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        float t;
        Point2f uv;
        if (!shape->intersect(lane(ray, args->N, i), t, uv)) continue;
        RTCRayN_tfar(ray, args->N, i) = t;
        RTCHitN_u(hit, args->N, i) = uv.x;
        RTCHitN_v(hit, args->N, i) = uv.y;
        RTCHitN_primID(hit, args->N, i) = args->primID;
        RTCHitN_geomID(hit, args->N, i) = args->geomID;
        RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
    }
}

void userOccluded(const RTCOccludedFunctionNArguments* args) {
    const auto* shape = static_cast<const IShape*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        float t;
        Point2f uv;
        if (shape->intersect(lane(args->ray, args->N, i), t, uv)) RTCRayN_tfar(args->ray, args->N, i) = -Infinity;
    }
}

class Embree final : public Implements<IIntersect> {
public:
    static Schema schema() {
        Schema s("accelerator", "embree", "Intel Embree 3 BVH (default accelerator); packets of 8 (AVX2) or 16 (AVX-512) rays for batches.");
        s.cite("Wald et al. 2014, Embree: A Kernel Framework for Efficient CPU Ray Tracing, ACM TOG 33(4)");
        s.boolean("robust", true,
                  "Robust traversal: no missed hits on edges and vertices, about 20 % slower rays (Mitsuba 3's "
                  "default is off; a scene-level embree_use_robust_intersections sets it)");
        s.string("batch", "packet",
                 "How batches of rays are traced: packet (8 or 16 wide, as the CPU's vectors), packet8 or packet16 "
                 "(that width on any CPU), stream (rtcIntersect1M), single")
            .oneOf({"packet", "packet8", "packet16", "stream", "single"});
        s.string("bvh", "two-level",
                 "two-level: a BVH per shape under a top-level BVH over the shapes (fastest measured on scenes of "
                 "a few large shapes, equal on large meshes); flat: one BVH over all triangles, with spatial splits")
            .oneOf({"two-level", "flat"});
        // Both packet widths on every machine: the one the CPU does not pick is checked too.
        s.addConformance({"default", {}});
        s.addConformance({"packets of 8", {{"batch", std::string("packet8")}}});
        s.addConformance({"packets of 16", {{"batch", std::string("packet16")}}});
        s.addConformance({"flat BVH", {{"bvh", std::string("flat")}}});
        return s;
    }

    explicit Embree(const Properties& p) : m_robust(p.getBool("robust")), m_flat(p.getString("bvh") == "flat") {
        const std::string batch = p.getString("batch");
        m_device = rtcNewDevice(nullptr);
        if (!m_device) fail("embree: cannot create a device (error {})", int(rtcGetDeviceError(nullptr)));
        rtcSetDeviceErrorFunction(m_device, onEmbreeError, nullptr);
        // Packets as wide as the CPU's vectors: 16 lanes need AVX-512; on an AVX2 machine
        // packets of 16 gave 4 % fewer samples/s than packets of 8 (bench/RESULTS.md).
        const bool native16 = rtcGetDeviceProperty(m_device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0;
        m_batch = batch == "stream"     ? Batch::Stream
                  : batch == "single"   ? Batch::Single
                  : batch == "packet16" ? Batch::Packet16
                  : batch == "packet8"  ? Batch::Packet8
                  : native16            ? Batch::Packet16
                                        : Batch::Packet8;
    }
    ~Embree() override {
        if (m_scene) rtcReleaseScene(m_scene);
        if (m_device) rtcReleaseDevice(m_device);
    }

    void build(std::span<const IShape* const> shapes) override {
        m_scene = rtcNewScene(m_device);
        rtcSetSceneFlags(m_scene, m_robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
        // Embree builds a two-level BVH for build quality "low" (see the header).
        rtcSetSceneBuildQuality(m_scene, m_flat ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_LOW);
        for (unsigned id = 0; id < shapes.size(); ++id) {
            const IShape* shape = shapes[id];
            m_bbox.expand(shape->bbox());
            RTCGeometry geom = shape->mesh() ? triangles(*shape->mesh()) : user(shape);
            rtcCommitGeometry(geom);
            rtcAttachGeometryByID(m_scene, geom, id);
            rtcReleaseGeometry(geom);
        }
        rtcCommitScene(m_scene);
    }

    bool intersect(const Ray& ray, Hit& hit) const override {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRayHit rh;
        setRay(rh.ray, ray);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(m_scene, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
        hit = Hit{rh.ray.tfar, rh.hit.geomID, rh.hit.primID, {rh.hit.u, rh.hit.v}};
        return true;
    }

    bool occluded(const Ray& ray) const override {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRay r;
        setRay(r, ray);
        rtcOccluded1(m_scene, &ctx, &r);
        return r.tfar < 0.f;
    }

    void intersect(std::span<const Ray> rays, std::span<Hit> hits) const override {
        if (m_batch == Batch::Single) return IIntersect::intersect(rays, hits);
        if (m_batch == Batch::Stream) return intersectStream(rays, hits);
        if (m_batch == Batch::Packet16) return intersectPackets<16, RTCRayHit16>(rays, hits);
        intersectPackets<8, RTCRayHit8>(rays, hits);
    }

    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> out) const override {
        if (m_batch == Batch::Single) return IIntersect::occluded(rays, out);
        if (m_batch == Batch::Stream) return occludedStream(rays, out);
        if (m_batch == Batch::Packet16) return occludedPackets<16, RTCRay16>(rays, out);
        occludedPackets<8, RTCRay8>(rays, out);
    }

    BBox3f bbox() const override { return m_bbox; }

private:
    enum class Batch { Packet8, Packet16, Stream, Single };

    /// Packets of W rays (8 or 16, see m_batch); the last packet's
    /// unused lanes repeat its last ray, masked off.
    template <int W, class RayHitW>
    void intersectPackets(std::span<const Ray> rays, std::span<Hit> hits) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        for (std::size_t base = 0; base < rays.size(); base += W) {
            alignas(64) int valid[W];
            RayHitW rh;
            std::size_t n = std::min<std::size_t>(W, rays.size() - base);
            for (std::size_t j = 0; j < W; ++j) {
                valid[j] = j < n ? -1 : 0;
                setLane(rh.ray, j, rays[base + std::min(j, n - 1)]);
                rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
            }
            if constexpr (W == 16) rtcIntersect16(valid, m_scene, &ctx, &rh);
            else rtcIntersect8(valid, m_scene, &ctx, &rh);
            for (std::size_t j = 0; j < n; ++j)
                hits[base + j] = rh.hit.geomID[j] == RTC_INVALID_GEOMETRY_ID
                                     ? Hit{}
                                     : Hit{rh.ray.tfar[j], rh.hit.geomID[j], rh.hit.primID[j], {rh.hit.u[j], rh.hit.v[j]}};
        }
    }
    template <int W, class RayW>
    void occludedPackets(std::span<const Ray> rays, std::span<std::uint8_t> out) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        for (std::size_t base = 0; base < rays.size(); base += W) {
            alignas(64) int valid[W];
            RayW r;
            std::size_t n = std::min<std::size_t>(W, rays.size() - base);
            for (std::size_t j = 0; j < W; ++j) {
                valid[j] = j < n ? -1 : 0;
                setLane(r, j, rays[base + std::min(j, n - 1)]);
            }
            if constexpr (W == 16) rtcOccluded16(valid, m_scene, &ctx, &r);
            else rtcOccluded8(valid, m_scene, &ctx, &r);
            for (std::size_t j = 0; j < n; ++j) out[base + j] = r.tfar[j] < 0.f ? 1 : 0;
        }
    }

    /// Embree's stream mode: it regroups the rays into packets itself.
    void intersectStream(std::span<const Ray> rays, std::span<Hit> hits) const {
        thread_local std::vector<RTCRayHit> buf;
        buf.resize(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) {
            setRay(buf[i].ray, rays[i]);
            buf[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
            buf[i].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        }
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rtcIntersect1M(m_scene, &ctx, buf.data(), unsigned(buf.size()), sizeof(RTCRayHit));
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const RTCRayHit& rh = buf[i];
            hits[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID
                          ? Hit{}
                          : Hit{rh.ray.tfar, rh.hit.geomID, rh.hit.primID, {rh.hit.u, rh.hit.v}};
        }
    }
    void occludedStream(std::span<const Ray> rays, std::span<std::uint8_t> out) const {
        thread_local std::vector<RTCRay> buf;
        buf.resize(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) setRay(buf[i], rays[i]);
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rtcOccluded1M(m_scene, &ctx, buf.data(), unsigned(buf.size()), sizeof(RTCRay));
        for (std::size_t i = 0; i < rays.size(); ++i) out[i] = buf[i].tfar < 0.f ? 1 : 0;
    }

    // Embree accepts t = tnear; IIntersect promises t in (0, tMax), so a ray starting
    // exactly on a surface must not report it at t = 0 (or −0).
    static constexpr float MinT = std::numeric_limits<float>::min();

    static void setRay(RTCRay& r, const Ray& ray) {
        r.org_x = ray.o.x, r.org_y = ray.o.y, r.org_z = ray.o.z;
        r.dir_x = ray.d.x, r.dir_y = ray.d.y, r.dir_z = ray.d.z;
        r.tnear = MinT;
        r.tfar = ray.tMax;
        r.time = ray.time;
        r.mask = 0xffffffffu;
        r.id = 0;
        r.flags = 0;
    }
    template <class RayW>
    static void setLane(RayW& r, std::size_t j, const Ray& ray) {
        r.org_x[j] = ray.o.x, r.org_y[j] = ray.o.y, r.org_z[j] = ray.o.z;
        r.dir_x[j] = ray.d.x, r.dir_y[j] = ray.d.y, r.dir_z[j] = ray.d.z;
        r.tnear[j] = MinT;
        r.tfar[j] = ray.tMax;
        r.time[j] = ray.time;
        r.mask[j] = 0xffffffffu;
        r.id[j] = unsigned(j);
        r.flags[j] = 0;
    }

    RTCGeometry triangles(const TriangleMesh& mesh) const {
        RTCGeometry g = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree-owned buffers carry the padding Embree reads past the last vertex.
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), mesh.vertexCount()));
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.triangleCount()));
        if (!v || !idx) fail("embree: out of memory for a mesh of {} triangles", mesh.triangleCount());
        std::memcpy(v, mesh.positions.data(), mesh.vertexCount() * 3 * sizeof(float));
        std::memcpy(idx, mesh.indices.data(), mesh.indices.size() * sizeof(unsigned));
        return g;
    }

    RTCGeometry user(const IShape* shape) const {
        RTCGeometry g = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(g, 1);
        rtcSetGeometryUserData(g, const_cast<IShape*>(shape));
        rtcSetGeometryBoundsFunction(g, userBounds, nullptr);
        rtcSetGeometryIntersectFunction(g, userIntersect);
        rtcSetGeometryOccludedFunction(g, userOccluded);
        return g;
    }

    bool m_robust;
    bool m_flat;
    Batch m_batch = Batch::Packet8;
    RTCDevice m_device = nullptr;
    RTCScene m_scene = nullptr;
    BBox3f m_bbox;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Embree)

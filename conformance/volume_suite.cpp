// Volume suite: an IVolume, in each of its configurations, against the promises of
// include/effigi/interfaces/ivolume.hpp. Probes: random points of the domain (the unit
// cube through toWorld()), around it (the unit cube scaled 3× about its centre), far off
// (±1e6) and non-finite, at random and extreme (360, 830 nm) wavelengths.
//  - finite: eval() and evalFloat() finite and ≥ 0 everywhere (a volume holds densities
//    and albedos), maxValue() finite;
//  - bounded: eval() (every wavelength) and evalFloat() ≤ maxValue();
//  - maxIn: over random boxes in and around the domain (sizes from a tenth of a voxel to
//    the whole domain), eval() and evalFloat() at points inside the box (corners and
//    faces included) ≤ maxIn(box) ≤ maxValue() — a majorant grid built from maxIn must
//    bound the medium at every point of each cell;
//  - bbox: bbox() is the bounding box of toWorld() applied to the unit cube's corners;
//  - constant: a volume saying isConstant() reads the same everywhere;
//  - voxel centres (grids with filter_type): at the centre of a voxel, trilinear and
//    nearest lookups agree (interpolation weights are 0 and 1 there), and half way
//    between two neighbouring centres the trilinear value is the mean of theirs;
//  - to_world: the volume made with to_world = M · (its to_world) reads at M p what the
//    original reads at p (points kept 0.1 voxel away from voxel faces, where the nearest
//    lookup may round either way).
// Deterministic checks; tolerances: 1e-6 relative for bounds (float rounding of a
// blend), 1e-4 of maxValue() for values compared after a transform.
#include "conformance/media_common.hpp"
#include "effigi/interfaces/ivolume.hpp"

#include <cmath>
#include <limits>

namespace effigi::conform::media {

namespace {

Point3f unitToWorld(const IVolume& v, const Point3f& u) { return v.toWorld().point(u); }

Point3f randomUnit(PCG32& rng, float lo = 0.f, float hi = 1.f) {
    return Point3f(lo + (hi - lo) * rng.nextFloat(), lo + (hi - lo) * rng.nextFloat(), lo + (hi - lo) * rng.nextFloat());
}

bool within(const SampledSpectrum& s, double bound) {
    for (int k = 0; k < NSpectrumSamples; ++k)
        if (!(double(s[k]) <= bound * (1.0 + 1e-6) + 1e-30)) return false;
    return true;
}

std::string pt(const Point3f& p) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", p.x, p.y, p.z); }

void checkValues(Target& t, const IVolume& v) {
    PCG32 rng = t.rng("values");
    const float maxV = v.maxValue();
    std::vector<Point3f> points;
    for (std::uint64_t i = 0, n = t.count(20000, 4000); i < n; ++i)
        points.push_back(unitToWorld(v, i % 4 == 3 ? randomUnit(rng, -1.f, 2.f) : randomUnit(rng)));
    const float inf = Infinity, nan = std::numeric_limits<float>::quiet_NaN();
    for (float a : {1e6f, -1e6f, inf, -inf, nan}) points.push_back(Point3f(a, 0.3f * a, -a)), points.push_back(Point3f(a));
    Tally fin, bound, cons;
    const SampledWavelengths fixed = SampledWavelengths::constant(550.f);
    const SampledSpectrum first = v.eval(points.front(), fixed);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Point3f& p = points[i];
        const SampledWavelengths l = probeWavelengths(rng, i);
        const SampledSpectrum s = v.eval(p, l);
        const float f = v.evalFloat(p);
        const std::string at = fmt::format("p = {}, λ0 = {:.1f} nm: eval {}, evalFloat {}", pt(p), l[0], spec(s), f);
        fin.note(s.isFinite() && nonNegative(s) && std::isfinite(f) && f >= 0.f, at);
        bound.note(within(s, maxV) && within(SampledSpectrum(f), maxV), at + fmt::format(", maxValue {}", maxV));
        if (v.isConstant()) {
            const SampledSpectrum here = v.eval(p, fixed);
            cons.note(here[0] == first[0], fmt::format("{} at {}, {} at {}", here[0], pt(p), first[0], pt(points[0])));
        }
    }
    t.expect("finite", fin.bad == 0 && std::isfinite(maxV), fin.figure(), fin.detail("eval, evalFloat finite and ≥ 0"));
    t.expect("bounded", bound.bad == 0, fmt::format("maxValue {:.6g}", maxV), bound.detail("eval, evalFloat ≤ maxValue"));
    if (v.isConstant()) t.expect("constant", cons.bad == 0, cons.figure(), cons.detail("the same value everywhere"));
    else t.skip("constant", "the volume is not constant");
}

void checkMaxIn(Target& t, const IVolume& v) {
    PCG32 rng = t.rng("maxIn");
    const glm::ivec3 res = v.resolution();
    const float voxel = 1.f / float(std::max({res.x, res.y, res.z}));
    const float maxV = v.maxValue();
    Tally tally;
    for (std::uint64_t b = 0, n = t.count(2000, 400); b < n; ++b) {
        // A box about a random point of [−0.25, 1.25]³, sized 0.1 voxel to the whole cube.
        const Point3f c = randomUnit(rng, -0.25f, 1.25f);
        const float size = std::min(1.f, voxel * std::pow(10.f, 2.f * rng.nextFloat() - 1.f));
        const Vector3f half = 0.5f * size * randomUnit(rng, 0.2f, 1.f);
        BBox3f box;
        for (int k = 0; k < 8; ++k)
            box.expand(unitToWorld(v, c + Vector3f(k & 1 ? half.x : -half.x, k & 2 ? half.y : -half.y,
                                                  k & 4 ? half.z : -half.z)));
        const float m = v.maxIn(box);
        std::string bad;
        if (!(m <= maxV * (1.f + 1e-6f))) bad = fmt::format("maxIn {} above maxValue {}", m, maxV);
        for (int j = 0; j < 32 && bad.empty(); ++j) {
            Point3f u = randomUnit(rng);
            for (int a = 0; a < 3 && j < 8; ++a) u[a] = (j >> a) & 1 ? 1.f : 0.f;  // the corners first
            if (j >= 8 && j < 16) u[j % 3] = j & 1 ? 1.f : 0.f;                  // then faces
            const Point3f p = box.min + u * box.extents();
            const SampledWavelengths l = probeWavelengths(rng, std::size_t(j));
            const SampledSpectrum s = v.eval(p, l);
            if (!within(s, m) || !within(SampledSpectrum(v.evalFloat(p)), m))
                bad = fmt::format("eval {} / evalFloat {} at {} above maxIn {} of box {} – {}", spec(s), v.evalFloat(p),
                                  pt(p), m, pt(box.min), pt(box.max));
        }
        tally.note(bad.empty(), bad);
    }
    t.expect("maxIn", tally.bad == 0, tally.figure(), tally.detail("eval ≤ maxIn(box) ≤ maxValue at points of the box"));
}

void checkBBox(Target& t, const IVolume& v) {
    BBox3f expect;
    for (int c = 0; c < 8; ++c) expect.expand(unitToWorld(v, Point3f(c & 1, (c >> 1) & 1, (c >> 2) & 1)));
    const BBox3f b = v.bbox();
    const float scale = std::max(1.f, std::max(maxAbsComponent(expect.min), maxAbsComponent(expect.max)));
    const float err = std::max(maxAbsComponent(b.min - expect.min), maxAbsComponent(b.max - expect.max));
    t.expect("bbox", err <= 1e-5f * scale, fmt::format("{} – {}", pt(b.min), pt(b.max)),
             fmt::format("toWorld(unit cube) spans {} – {}", pt(expect.min), pt(expect.max)));
}

/// The variant with `overrides`, or null (reported) if it cannot be made.
Ref<IVolume> variant(Target& t, const ParamList& overrides, const std::string& check) {
    try {
        return query<IVolume>(t.create(overrides));
    } catch (const std::exception& e) {
        t.expect(check, false, "-", fmt::format("cannot make the variant: {}", e.what()));
        return nullptr;
    }
}

void checkVoxelCentres(Target& t, const IVolume& v) {
    const glm::ivec3 n = v.resolution();
    if (!t.hasParameter("filter_type") || n == glm::ivec3(1)) {
        t.skip("voxel centres", "not a grid with filter_type");
        return;
    }
    Ref<IVolume> lin = variant(t, {{"filter_type", std::string("trilinear")}}, "voxel centres");
    Ref<IVolume> near = variant(t, {{"filter_type", std::string("nearest")}}, "voxel centres");
    if (!lin || !near) return;
    PCG32 rng = t.rng("voxel centres");
    const double tol = 1e-4 * std::max(1e-6f, v.maxValue());
    Tally tally;
    for (std::uint64_t i = 0, count = t.count(4000, 1000); i < count; ++i) {
        const glm::ivec3 c(int(rng.nextUInt() % std::uint32_t(n.x)), int(rng.nextUInt() % std::uint32_t(n.y)),
                           int(rng.nextUInt() % std::uint32_t(n.z)));
        const int axis = int(rng.nextUInt() % 3u);
        glm::ivec3 d = c;
        d[axis] = c[axis] + 1 < n[axis] ? c[axis] + 1 : c[axis] - 1;
        auto centre = [&](const glm::ivec3& k) { return (Point3f(k) + 0.5f) / Point3f(n); };
        const SampledWavelengths l = probeWavelengths(rng, std::size_t(i));
        const Point3f pc = unitToWorld(v, centre(c)), pd = unitToWorld(v, centre(d)),
                      pm = unitToWorld(v, 0.5f * (centre(c) + centre(d)));
        const SampledSpectrum a = lin->eval(pc, l), na = near->eval(pc, l), b = near->eval(pd, l), mid = lin->eval(pm, l);
        std::string bad;
        for (int k = 0; k < NSpectrumSamples && bad.empty(); ++k) {
            if (std::abs(double(a[k]) - na[k]) > tol)
                bad = fmt::format("voxel ({}, {}, {}): trilinear {} ≠ nearest {}", c.x, c.y, c.z, spec(a), spec(na));
            else if (std::abs(double(mid[k]) - 0.5 * (double(na[k]) + b[k])) > tol)
                bad = fmt::format("between voxels ({}, {}, {}) and ({}, {}, {}): {} ≠ mean of {} and {}", c.x, c.y, c.z,
                                  d.x, d.y, d.z, spec(mid), spec(na), spec(b));
        }
        tally.note(bad.empty(), bad);
    }
    t.expect("voxel centres", tally.bad == 0, tally.figure(),
             tally.detail(fmt::format("exact at centres, linear between them (±{:.2g})", tol)));
}

void checkToWorld(Target& t, const IVolume& v) {
    if (!t.hasParameter("to_world") || v.isConstant()) {
        t.skip("to_world", "a constant volume, or no to_world");
        return;
    }
    Transform base;
    for (const auto& [name, value] : t.configuration().params)
        if (name == "to_world") base = std::get<Transform>(value);
    const Transform m = Transform::translate({3.f, -1.f, 0.5f}) * Transform::rotate({0.3f, -1.f, 0.6f}, 70.f) *
                        Transform::scale({1.5f, 0.7f, 2.f});
    Ref<IVolume> moved = variant(t, {{"to_world", m * base}}, "to_world");
    if (!moved) return;
    PCG32 rng = t.rng("to_world");
    const glm::ivec3 n = v.resolution();
    const double tol = 1e-4 * std::max(1e-6f, v.maxValue());
    Tally tally;
    for (std::uint64_t i = 0, count = t.count(4000, 1000); i < count; ++i) {
        // A voxel centre of [−1, 2]³ (outside: wrap modes), moved at most 0.4 voxel.
        Point3f u;
        for (int a = 0; a < 3; ++a)
            u[a] = (std::floor(3.f * n[a] * rng.nextFloat()) - float(n[a]) + 0.5f + 0.8f * (rng.nextFloat() - 0.5f)) / n[a];
        const Point3f p = unitToWorld(v, u);
        const SampledWavelengths l = probeWavelengths(rng, std::size_t(i));
        const SampledSpectrum a = v.eval(p, l), b = moved->eval(m.point(p), l);
        bool ok = std::abs(double(v.evalFloat(p)) - moved->evalFloat(m.point(p))) <= tol;
        for (int k = 0; k < NSpectrumSamples; ++k) ok = ok && std::abs(double(a[k]) - b[k]) <= tol;
        tally.note(ok, fmt::format("at {}: {}; moved, at {}: {}", pt(p), spec(a), pt(m.point(p)), spec(b)));
    }
    t.expect("to_world", tally.bad == 0, tally.figure(),
             tally.detail(fmt::format("the moved volume reads the same at the moved point (±{:.2g})", tol)));
}

void runVolumeSuite(Target& t) {
    Ref<IVolume> v = t.as<IVolume>();
    if (!v) {
        t.expect("interface", false, "-", "component does not implement IVolume");
        return;
    }
    checkValues(t, *v);
    checkMaxIn(t, *v);
    checkBBox(t, *v);
    checkVoxelCentres(t, *v);
    checkToWorld(t, *v);
    const glm::ivec3 n = v->resolution();
    t.info("resolution", fmt::format("{}×{}×{}", n.x, n.y, n.z), fmt::format("maxValue {:.6g}", v->maxValue()));
}

} // namespace

} // namespace effigi::conform::media

EFFIGI_CONFORMANCE_SUITE("volume", "finite, ≥ 0, bounded by maxValue and maxIn; voxel centres; bbox and to_world",
                         effigi::conform::media::runVolumeSuite);

// Accelerator suite: every IIntersect answers closest-hit and any-hit queries like the
// reference, `bruteforce`, on generated scenes (accelerator_scenes.cpp): a random
// triangle soup with analytic shapes, the Cornell box, a large mesh (checked against
// bruteforce on a subset of its rays and against embree, bvh and kdtree on all of them),
// and stiff ones — coordinates at 1e6 and 1e-6, slivers, coplanar overlaps, rays through
// vertices and along edges, rays starting on surfaces, axis-aligned directions, tMax at
// the hit distance, grazing rays — and csg solids (shape/csg) among triangles.
//
// Agreement: the same hit or miss, and on a hit the same shape and primitive with
// |Δt| ≤ 1e-4 t and |Δu|, |Δv| ≤ 1e-4. A ray on which the answers differ otherwise goes
// to the arbiter (AccelArbiter), which decides in double precision whether the geometry
// allows the answer: exact ties (coplanar and duplicate triangles, shared edges) and
// ill-posed rays (hits within float rounding of an edge, of the ray origin or of tMax)
// admit several answers, and the arbiter accepts exactly those it can show rounding
// allows. Anything else is a disagreement, and one fails the check.
#include "conformance/accelerator_scenes.hpp"
#include "conformance/conformance.hpp"

#include "effigi/interfaces/iintersect.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <map>
#include <mutex>

namespace effigi::conform {

namespace {

double now() {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}

constexpr double TolT = 1e-4, TolUV = 1e-4;
/// The accelerators the large mesh is cross-checked against, pairwise.
const char* const Peers[] = {"embree", "bvh", "kdtree"};

struct Answers {
    std::vector<AccelAnswer> single, batch;  // batch: the span queries (soup only)
    std::size_t rays = 0, missWrites = 0;     // misses that wrote into the Hit
    double buildMs = 0.0, closestSeconds = 0.0, anySeconds = 0.0, batchSeconds = 0.0;
    std::string error;
};

/// Seconds per run of f: the fastest of up to 5 runs while they add up to less than 20 ms
/// (a short loop timed once is at the mercy of one context switch).
template <typename F> double timed(F&& f) {
    double best = Infinity, total = 0.0;
    for (int r = 0; r < 5 && total < 0.02; ++r) {
        double t0 = now();
        f();
        double dt = now() - t0;
        best = std::min(best, dt);
        total += dt;
    }
    return best;
}

Answers answer(IIntersect& acc, const AccelScene& s, std::size_t n) {
    Answers out;
    out.rays = n;
    out.single.resize(n);
    double t0 = now();
    acc.build(s.shapes);
    out.buildMs = 1e3 * (now() - t0);
    const Hit sentinel{-7.f, 0xfffffffeu, 0xfffffffeu, {-7.f, -7.f}};
    out.closestSeconds = timed([&] {
        out.missWrites = 0;
        for (std::size_t i = 0; i < n; ++i) {
            Hit h = sentinel;
            AccelAnswer& a = out.single[i];
            a.returned = acc.intersect(s.rays[i], h);
            a.hit = a.returned ? h : Hit{};
            if (!a.returned && (h.t != sentinel.t || h.shape != sentinel.shape || h.prim != sentinel.prim || h.uv != sentinel.uv))
                ++out.missWrites;
        }
    });
    out.anySeconds = timed([&] {
        for (std::size_t i = 0; i < n; ++i) out.single[i].occluded = acc.occluded(s.rays[i]);
    });
    if (s.name == "soup") {  // the batch entry points, which Embree answers with packets
        std::vector<Hit> hits(n);
        std::vector<std::uint8_t> occ(n);
        out.batchSeconds = timed([&] {
            acc.intersect(std::span(s.rays.data(), n), std::span(hits));
            acc.occluded(std::span(s.rays.data(), n), std::span(occ));
        });
        out.batch.resize(n);
        for (std::size_t i = 0; i < n; ++i) out.batch[i] = AccelAnswer{hits[i], hits[i].valid(), occ[i] != 0};
    }
    return out;
}

Answers answerWith(Registry& reg, const std::string& name, const ParamList& params, const AccelScene& s, std::size_t n) {
    try {
        Properties p("accelerator", name);
        for (const auto& [k, v] : params) p.set(k, v);
        Ref<IIntersect> acc = query<IIntersect>(reg.create("accelerator", name, p));
        if (!acc) fail("accelerator '{}' does not implement IIntersect", name);
        return answer(*acc, s, n);
    } catch (const std::exception& e) {
        Answers a;
        a.error = e.what();
        return a;
    }
}

// ---- shared scenes and answers -------------------------------------------------------
// Scenes depend only on the seed, --quick and their name, so bruteforce's answers (and,
// for the large mesh, the peers') are computed once per run and shared by every target.

struct PeerSlot {
    std::once_flag once;
    Answers answers;
};

struct SceneSlot {
    std::once_flag once;
    AccelScene scene;
    Answers reference;
    std::unique_ptr<AccelArbiter> arbiter;
    std::mutex mutex;
    std::map<std::string, std::shared_ptr<PeerSlot>> peers;
};

std::size_t raysFor(const AccelScene& s, const std::string& component) {
    return s.large && component == "bruteforce" ? s.referenceRays : s.rays.size();
}

SceneSlot& sceneSlot(Target& t, const std::string& name) {
    static std::mutex mutex;
    static std::map<std::string, std::shared_ptr<SceneSlot>> slots;
    std::shared_ptr<SceneSlot> slot;
    {
        std::lock_guard lock(mutex);
        auto& s = slots[fmt::format("{:x}/{}/{}", t.seed(), t.quick(), name)];
        if (!s) s = std::make_shared<SceneSlot>();
        slot = s;
    }
    std::call_once(slot->once, [&] {
        slot->scene = makeAccelScene(name, t.registry(), t.seed(), t.quick());
        slot->reference = answerWith(t.registry(), "bruteforce", {}, slot->scene, slot->scene.referenceRays);
        slot->arbiter = std::make_unique<AccelArbiter>(slot->scene);
    });
    return *slot;  // slots live as long as the process
}

const Answers& peerAnswers(Target& t, SceneSlot& slot, const std::string& name) {
    std::shared_ptr<PeerSlot> ps;
    {
        std::lock_guard lock(slot.mutex);
        auto& p = slot.peers[name];
        if (!p) p = std::make_shared<PeerSlot>();
        ps = p;
    }
    std::call_once(ps->once, [&] {
        ps->answers = answerWith(t.registry(), name, {}, slot.scene, raysFor(slot.scene, name));
    });
    return ps->answers;
}

// ---- comparison ----------------------------------------------------------------------

struct Tally {
    std::size_t compared = 0, differ = 0, bad = 0, unjudged = 0;
    double worstRel = 0.0;  // over rays where both hit the same primitive
    std::string first;      // the first bad ray
    std::vector<std::string> parts;
};

std::string rayText(const Ray& r) {
    return fmt::format("o = ({:.9g}, {:.9g}, {:.9g}), d = ({:.9g}, {:.9g}, {:.9g}), tMax = {:.9g}", r.o.x, r.o.y, r.o.z,
                       r.d.x, r.d.y, r.d.z, r.tMax);
}
std::string hitText(const AccelAnswer& a) {
    if (a.returned != a.hit.valid()) return fmt::format("returned {} with hit.shape = {}", a.returned, a.hit.shape);
    if (!a.hit.valid()) return "miss";
    return fmt::format("shape {} prim {} t = {:.9g} uv = ({:.6g}, {:.6g})", a.hit.shape, a.hit.prim, a.hit.t, a.hit.uv.x,
                       a.hit.uv.y);
}

bool sameHit(const Hit& r, const Hit& x, double& rel) {
    if (r.shape != x.shape || r.prim != x.prim) return false;
    rel = std::abs(double(x.t) - double(r.t)) / std::abs(double(r.t));
    if (std::isnan(rel)) rel = Infinity;
    return rel <= TolT && std::abs(x.uv.x - r.uv.x) <= TolUV && std::abs(x.uv.y - r.uv.y) <= TolUV;
}

/// Compares `mine` with `ref` on rays [0, n); disagreements go to the arbiter while the
/// budget lasts (each costs a pass over the scene in double precision).
void compare(const SceneSlot& slot, const std::string& refName, const std::vector<AccelAnswer>& ref,
             const std::vector<AccelAnswer>& mine, std::size_t n, bool closest, Tally& tally, std::size_t& budget) {
    std::size_t differ = 0, bad = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const AccelAnswer &r = ref[i], &a = mine[i];
        bool agree;
        if (closest) {
            double rel = 0.0;
            bool same = a.returned == a.hit.valid() && r.hit.valid() == a.hit.valid() &&
                        (!a.hit.valid() || sameHit(r.hit, a.hit, rel));
            // Hits at a distance below 1e-3 of the scene's size are rays leaving a surface
            // they start on: there t is all rounding, and its relative error meaningless.
            if (a.hit.valid() && r.hit.valid() && a.hit.shape == r.hit.shape && a.hit.prim == r.hit.prim &&
                double(r.hit.t) * glm::length(Vector3d(slot.scene.rays[i].d)) > 1e-3 * slot.scene.extent)
                tally.worstRel = std::max(tally.worstRel, rel);
            agree = same;
        } else {
            agree = a.occluded == r.occluded;
        }
        if (agree) continue;
        ++differ;
        bool ok = false;
        if (budget > 0) {
            --budget;
            const Ray& ray = slot.scene.rays[i];
            ok = closest ? slot.arbiter->acceptClosest(ray, a) : slot.arbiter->acceptAny(ray, a);
        } else {
            ++tally.unjudged;
        }
        if (!ok && bad++ == 0 && tally.first.empty())
            tally.first = fmt::format("ray {}: {}; {}: {}{}, this: {}{}", i, rayText(slot.scene.rays[i]), refName,
                                      hitText(r), closest ? "" : fmt::format(" occluded {}", r.occluded), hitText(a),
                                      closest ? "" : fmt::format(" occluded {}", a.occluded));
    }
    tally.compared += n;
    tally.differ += differ;
    tally.bad += bad;
    tally.parts.push_back(fmt::format("vs {} on {} rays: {} differ, {} accepted by the arbiter", refName, n, differ, differ - bad));
}

void report(Target& t, const std::string& check, const AccelScene& scene, const Tally& tally, bool closest,
            std::size_t missWrites) {
    std::string detail = scene.description + "; ";
    for (std::size_t i = 0; i < tally.parts.size(); ++i) detail += (i ? "; " : "") + tally.parts[i];
    if (closest)
        detail += fmt::format(". Max Δt/t {:.2g} over rays hitting the same primitive farther than 1e-3 of the scene "
                              "size (tolerance {:g})", tally.worstRel, TolT);
    if (tally.unjudged) detail += fmt::format("; {} differences left unjudged (arbiter budget spent)", tally.unjudged);
    if (missWrites) detail += fmt::format("; intersect() wrote into the Hit on {} misses", missWrites);
    if (!tally.first.empty()) detail += "; first bad: " + tally.first;
    std::string figure = fmt::format("{}/{} bad", tally.bad, tally.compared);
    if (closest) figure += fmt::format(", max Δt/t {:.1e}", tally.worstRel);
    t.expect(check, tally.bad == 0 && missWrites == 0, figure, detail);
}

void runScene(Target& t, const std::string& name) {
    SceneSlot& slot = sceneSlot(t, name);
    const AccelScene& scene = slot.scene;
    const std::string closestCheck = "closest hit " + name, anyCheck = "any hit " + name;
    if (!slot.reference.error.empty()) {
        t.expect(closestCheck, false, "error", "the reference (bruteforce) failed: " + slot.reference.error);
        return;
    }
    const std::string& me = t.component();
    bool isPeer = t.config() == "default" && std::any_of(std::begin(Peers), std::end(Peers), [&](const char* p) { return me == p; });
    Answers own;
    const Answers* mine = &own;
    if (isPeer && scene.large) mine = &peerAnswers(t, slot, me);
    else own = answerWith(t.registry(), me, t.configuration().params, scene, raysFor(scene, me));
    if (!mine->error.empty()) {
        t.expect(closestCheck, false, "error", mine->error);
        return;
    }
    // Each arbitration is a pass over the scene's triangles: about 4e7 triangle views per
    // check at most (a few seconds), and at least 200 rays even on the large mesh.
    const std::size_t budgetPerCheck = std::max<std::size_t>(200, std::size_t(4e7) / (scene.triangles + 1));
    Tally closest, any;
    std::size_t budgetC = budgetPerCheck, budgetA = budgetPerCheck;
    std::size_t nRef = std::min(scene.referenceRays, mine->rays);
    compare(slot, "bruteforce", slot.reference.single, mine->single, nRef, true, closest, budgetC);
    compare(slot, "bruteforce", slot.reference.single, mine->single, nRef, false, any, budgetA);
    if (scene.large) {
        for (const char* peer : Peers) {
            if (me == peer) continue;
            const Answers& p = peerAnswers(t, slot, peer);
            if (!p.error.empty()) {
                closest.parts.push_back(fmt::format("{} not compared ({})", peer, p.error));
                continue;
            }
            std::size_t n = std::min(p.rays, mine->rays);
            compare(slot, peer, p.single, mine->single, n, true, closest, budgetC);
            compare(slot, peer, p.single, mine->single, n, false, any, budgetA);
        }
    }
    report(t, closestCheck, scene, closest, true, mine->missWrites);
    report(t, anyCheck, scene, any, false, 0);
    if (!mine->batch.empty()) {
        Tally bc, ba;
        std::size_t b1 = budgetPerCheck, b2 = budgetPerCheck;
        compare(slot, "bruteforce", slot.reference.single, mine->batch, nRef, true, bc, b1);
        compare(slot, "bruteforce", slot.reference.single, mine->batch, nRef, false, ba, b2);
        report(t, closestCheck + " (batch)", scene, bc, true, 0);
        report(t, anyCheck + " (batch)", scene, ba, false, 0);
    }
    auto rate = [&](double seconds) { return seconds > 0.0 ? double(mine->rays) / seconds * 1e-6 : 0.0; };
    std::string batch = mine->batch.empty() ? "" : fmt::format(", {:.3g} M/s batch (closest + any)", 2.0 * rate(mine->batchSeconds));
    t.info("time " + name,
           fmt::format("build {:.3g} ms, {:.3g} M/s closest, {:.3g} M/s any", mine->buildMs, rate(mine->closestSeconds),
                       rate(mine->anySeconds)),
           fmt::format("{} rays on one thread (other jobs may share the machine){}", mine->rays, batch));
}

void runAcceleratorSuite(Target& t) {
    if (!t.as<IIntersect>()) {
        t.expect("interface", false, "-", "component does not implement IIntersect");
        return;
    }
    for (const std::string& name : accelSceneNames()) runScene(t, name);
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("accelerator",
                         "closest and any hit against bruteforce on random, Cornell, large and stiff scenes; "
                         "build time and rays/s",
                         effigi::conform::runAcceleratorSuite);

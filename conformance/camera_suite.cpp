// Camera suite: an ICamera, in each of its configurations, with its configured film and
// with films of other shapes (wide, tall, a single pixel, a crop window), is checked for
// what ICamera and ICameraImportance promise:
//  - film maps into image: film positions over the full film [0, W] × [0, H], edges and
//    corners included, and lens samples at 0 and 1 − ε give finite rays with a unit
//    direction, a positive finite length and a finite, non-negative weight;
//  - clip range: a ray starts at camera depth near_clip and spans the clip slab, its
//    length times the cosine to the viewing axis being far_clip − near_clip (Mitsuba);
//    or, for a panoramic camera (it looks sideways and back, where no plane can clip),
//    starts at distance near_clip from the eye and runs far_clip − near_clip; every ray
//    of a camera must follow the same one of the two;
//  - projection inverts generateRay: points at several depths along a ray connect
//    (ICameraImportance::sampleDirection with the same lens sample) to the film position
//    the ray came from, within the rounding the geometry allows, with a connection
//    (wi, dist, weight, pdf) that is consistent;
//  - importance: the importance over the directions from a lens point (per unit area
//    across the viewing direction for an orthographic camera) is the density of
//    generateRay's directions (origins) for film positions uniform over the full film:
//    a chi-square test of the two, and its integral over the film is 1 within 1e-3
//    (Veach 1997, §8.1; the normalisation of icamera_importance.hpp).
// The chi-square test is the only statistical check: seeded from the run's seed and its
// name (Target::rng), its verdict is taken at the run's Šidák-corrected level (family-wise
// α = 0.01); every other check is deterministic with the tolerance it prints.
// Camera space is Mitsuba's: the camera looks along local +z of to_world.
#include "conformance/camera_chart.hpp"
#include "conformance/conformance.hpp"
#include "conformance/histogram.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/ifilm.hpp"

#include <fmt/format.h>

#include <cmath>

namespace effigi::conform {

void checkDirectionDensity(Target& t, const ICamera& cam, const ICameraImportance& imp);  // camera_density.cpp
void checkImportance(Target& t, const CameraSetup& s);                                    // camera_importance.cpp

namespace {

using Setup = CameraSetup;

Ref<IFilm> makeFilm(Registry& reg, int w, int h, int cx = 0, int cy = 0, int cw = 0, int ch = 0) {
    Properties p("film", "hdrfilm");
    p.set("width", std::int64_t(w));
    p.set("height", std::int64_t(h));
    if (cw > 0) {
        p.set("crop_offset_x", std::int64_t(cx));
        p.set("crop_offset_y", std::int64_t(cy));
        p.set("crop_width", std::int64_t(cw));
        p.set("crop_height", std::int64_t(ch));
    }
    return query<IFilm>(reg.create("film", "hdrfilm", p));
}

Setup setupOf(std::string label, Ref<ICamera> cam) {
    Setup s;
    s.label = std::move(label);
    s.cam = std::move(cam);
    s.imp = query<ICameraImportance>(s.cam.get());
    s.full = Vector2f(s.cam->film().fullSize());
    s.toWorld = glm::dmat4(s.cam->toWorld().matrix());
    s.toLocal = glm::inverse(s.toWorld);
    s.eye = glm::dvec3(s.toWorld[3]);
    s.around = seesAround(*s.cam);
    return s;
}

/// Film positions on the edges, corners and inside of the film (and of its crop window).
std::vector<Point2f> edgePositions(const Setup& s) {
    auto axis = [](float size, int off, int crop) {
        std::vector<float> v = {0.f, 1e-6f, 0.5f * size, std::nextafter(size, 0.f), size};
        if (size > 1.f) v.push_back(0.5f), v.push_back(size - 0.5f);
        if (crop > 0) v.push_back(float(off)), v.push_back(float(off + crop));
        return v;
    };
    const IFilm& f = s.cam->film();
    bool cropped = f.size() != f.fullSize();
    std::vector<float> xs = axis(s.full.x, f.cropOffset().x, cropped ? f.size().x : 0);
    std::vector<float> ys = axis(s.full.y, f.cropOffset().y, cropped ? f.size().y : 0);
    std::vector<Point2f> out;
    for (float x : xs)
        for (float y : ys) out.emplace_back(x, y);
    return out;
}

const Point2f EdgeLens[] = {{0.5f, 0.5f}, {0.f, 0.f}, {OneMinusEpsilon, OneMinusEpsilon}, {0.f, OneMinusEpsilon}};

/// Film maps into image, and clip range.
void checkRays(Target& t, const std::vector<Setup>& setups, double nearClip, double farClip, bool hasClip) {
    PCG32 rng = t.rng("film maps into image");
    Tally maps, clip;
    std::uint64_t planarOnly = 0, radialOnly = 0;  // rays that only one clip convention fits
    for (const Setup& s : setups) {
        glm::dvec3 axis = glm::normalize(glm::dvec3(s.toWorld * glm::dvec4(0, 0, 1, 0)));
        auto probe = [&](Point2f film, Point2f lens) {
            SampledSpectrum w(-1.f);
            Ray r = rayAt(s, film, lens, w);
            bool weightOk = true;
            for (int i = 0; i < NSpectrumSamples; ++i) weightOk = weightOk && std::isfinite(w[i]) && w[i] >= 0.f;
            double len = glm::length(glm::dvec3(r.d));
            bool ok = isFinite(r.o) && isFinite(r.d) && std::abs(len - 1.0) <= 1e-5 && std::isfinite(r.tMax) &&
                      r.tMax > 0.f && weightOk;
            maps.note(ok, fmt::format("{}: film {} lens {}: o = ({}, {}, {}), |d| = {}, tMax = {}, weight {}", s.label,
                                      str(film), str(lens), r.o.x, r.o.y, r.o.z, len, r.tMax, w[0]));
            if (!ok || !hasClip) return;
            // Depth of the origin is rounded like a point at |o| + |eye| from the origin.
            double depth = local(s, r.o).z;
            double tolStart = 1e-5 * nearClip + 64.0 * U * (glm::length(glm::dvec3(r.o)) + glm::length(s.eye));
            double span = double(r.tMax) * glm::dot(glm::dvec3(r.d), axis);
            double tolSpan = 1e-4 * (farClip - nearClip);
            bool planar = std::abs(depth - nearClip) <= tolStart && std::abs(span - (farClip - nearClip)) <= tolSpan;
            // Panoramic cameras (spherical, panoramic, fisheye) see sideways and backwards,
            // where no depth plane bounds a ray: they clip by distance from the eye.
            double radius = glm::length(glm::dvec3(r.o) - s.eye);
            bool radial = std::abs(radius - nearClip) <= tolStart && std::abs(double(r.tMax) - (farClip - nearClip)) <= tolSpan;
            if (planar != radial) ++(planar ? planarOnly : radialOnly);
            clip.note(planar || radial,
                      fmt::format("{}: film {} lens {}: origin depth {:.9g}, distance {:.9g} (near {:.9g}), tMax = {:.9g}, "
                                  "tMax·cos = {:.9g} (far − near = {:.9g})",
                                  s.label, str(film), str(lens), depth, radius, nearClip, r.tMax, span, farClip - nearClip));
        };
        for (Point2f film : edgePositions(s))
            for (Point2f lens : EdgeLens) probe(film, lens);
        for (std::uint64_t i = 0, n = t.count(4000, 1000); i < n; ++i)
            probe(Point2f(rng.nextFloat() * s.full.x, rng.nextFloat() * s.full.y), Point2f(rng.nextFloat(), rng.nextFloat()));
    }
    t.expect("film maps into image", maps.bad == 0, maps.figure(),
             maps.bad ? "first: " + maps.first
                      : "finite rays, |d| = 1 ± 1e-5, finite tMax > 0, finite weight ≥ 0 over the film, its edges and corners");
    if (!hasClip) {
        t.skip("clip range", "no near_clip / far_clip parameters");
        return;
    }
    bool mixed = planarOnly > 0 && radialOnly > 0;
    t.expect("clip range", clip.bad == 0 && !mixed, clip.figure(),
             clip.bad ? "first: " + clip.first
             : mixed  ? fmt::format("{} rays clip by depth, {} by distance: one convention per camera", planarOnly, radialOnly)
                      : "origins at depth near_clip and tMax·cos θ = far_clip − near_clip (projective), or at distance "
                        "near_clip from the eye and tMax = far_clip − near_clip (panoramic), one for all rays (to "
                        "rounding, 1e-4 relative)");
}

/// The distance between the point p and the line of r.
double lineDistance(const glm::dvec3& p, const Ray& r) {
    glm::dvec3 d = glm::normalize(glm::dvec3(r.d));
    return glm::length(glm::cross(p - glm::dvec3(r.o), d));
}

/// Projection inverts generateRay.
void checkInverse(Target& t, const std::vector<Setup>& setups) {
    PCG32 rng = t.rng("projection inverts generateRay");
    Tally proj, conn;
    double worstRatio = 0.0;
    for (const Setup& s : setups) {
        auto probe = [&](Point2f film, Point2f lens) {
            SampledSpectrum w;
            Ray r = rayAt(s, film, lens, w);
            if (!(isFinite(r.o) && isFinite(r.d) && std::isfinite(r.tMax))) return;  // film maps into image says so
            // World length of a film step of h pixels at the point: rays of neighbouring
            // film positions (toward the centre) through the same lens point.
            // Steps of up to 16 pixels, so that the rounding of the rays' origins is small
            // against the step.
            float hx = std::clamp(0.25f * s.full.x, 0.25f, 16.f), hy = std::clamp(0.25f * s.full.y, 0.25f, 16.f);
            if (film.x > 0.5f * s.full.x) hx = -hx;
            if (film.y > 0.5f * s.full.y) hy = -hy;
            Ray rx = rayAt(s, film + Point2f(hx, 0.f), lens, w), ry = rayAt(s, film + Point2f(0.f, hy), lens, w);
            for (double f : {1e-3, 0.02, 0.5, 0.98}) {
                Point3f p = r(float(f * double(r.tMax)));
                glm::dvec3 pd(p), exact = glm::dvec3(r.o) + f * double(r.tMax) * glm::dvec3(r.d);
                double perPixel = std::min(lineDistance(exact, rx) / std::abs(hx), lineDistance(exact, ry) / std::abs(hy));
                // Rounding of the film position, and of p and its camera-space image (a few
                // float roundings of |p| across the ray) as film pixels.
                double tol = 2e-3 + 4.0 * U * std::max(s.full.x, s.full.y) +
                             256.0 * U * (glm::length(pd) + glm::length(glm::dvec3(r.o)) + glm::length(s.eye)) / perPixel;
                CameraImportanceSample cs;
                bool ok = s.imp->sampleDirection(p, lens, cs);
                double err = ok ? glm::length(glm::dvec2(cs.pFilm) - glm::dvec2(film)) : HUGE_VAL;
                // A panorama's film may wrap: its left and right edges look the same way.
                for (double wrap : {-1.0, 1.0})
                    if (ok && s.around)
                        err = std::min(err, glm::length(glm::dvec2(cs.pFilm) + glm::dvec2(wrap * s.full.x, 0.0) -
                                                        glm::dvec2(film)));
                // A film position within tol of the film's edge may fall just outside it.
                double edge = std::min({double(film.x), double(film.y), s.full.x - double(film.x), s.full.y - double(film.y)});
                if (!ok && edge <= tol) continue;
                if (ok) worstRatio = std::max(worstRatio, err / tol);
                proj.note(err <= tol, fmt::format("{}: film {} lens {} at t = {:.4g} of {:.4g}: {} (tolerance {:.3g} px)",
                                                  s.label, str(film), str(lens), f * r.tMax, r.tMax,
                                                  ok ? "connects to film " + str(cs.pFilm) : std::string("no connection"),
                                                  tol));
                if (!ok) continue;
                // The connection: wi back along the ray (unless a delta direction, which is
                // the viewing direction), dist to pCamera, a positive finite weight and pdf.
                glm::dvec3 pc(cs.pCamera);
                double dist = glm::length(pd - pc);
                double angTol = 1e-5 + 64.0 * U * (glm::length(pd) + glm::length(s.eye)) / std::max(dist, 1e-30);
                glm::dvec3 wi = glm::normalize(glm::dvec3(cs.wi)), back = -glm::normalize(glm::dvec3(r.d));
                double ang = std::atan2(glm::length(glm::cross(wi, back)), glm::dot(wi, back));  // acos loses digits near 0
                bool good = std::abs(glm::length(glm::dvec3(cs.wi)) - 1.0) <= 1e-5 && ang <= angTol &&
                            std::abs(cs.dist - dist) <= 1e-4 * dist + 64.0 * U * (glm::length(pd) + glm::length(pc)) &&
                            std::isfinite(cs.weight) && cs.weight > 0.f && std::isfinite(cs.pdf) && cs.pdf > 0.f;
                conn.note(good, fmt::format("{}: film {} lens {} at t = {:.4g}: wi {:.3g} rad off −d, dist {} vs {}, "
                                            "weight {}, pdf {}",
                                            s.label, str(film), str(lens), f * r.tMax, ang, cs.dist, dist, cs.weight,
                                            cs.pdf));
            }
        };
        for (Point2f film : edgePositions(s)) probe(film, Point2f(0.5f));
        for (std::uint64_t i = 0, n = t.count(2000, 400); i < n; ++i)
            probe(Point2f(rng.nextFloat() * s.full.x, rng.nextFloat() * s.full.y), Point2f(rng.nextFloat(), rng.nextFloat()));
    }
    t.expect("projection inverts generateRay", proj.bad == 0, fmt::format("{}; worst {:.3g} of tolerance", proj.figure(), worstRatio),
             proj.bad ? "first: " + proj.first
                      : "points at 0.1 %, 2 %, 50 %, 98 % of each ray connect to its film position within 2e-3 px + "
                        "the rounding of the point's position");
    t.expect("connection geometry", conn.bad == 0, conn.figure(),
             conn.bad ? "first: " + conn.first
                      : "wi = −d, dist = |p − pCamera|, finite weight > 0 and pdf > 0 for every connection");
}

void runCameraSuite(Target& t) {
    Ref<ICamera> cam = t.as<ICamera>();
    if (!cam) {
        t.expect("interface", false, "-", "component does not implement ICamera");
        return;
    }
    Registry& reg = t.registry();
    // near_clip and far_clip as the configuration sets them (or their defaults).
    Properties p(t.tag(), t.component());
    for (const auto& [name, value] : t.configuration().params) p.set(name, value);
    reg.info(t.tag(), t.component()).schema.validate(p);
    const bool hasClip = p.has("near_clip") && p.has("far_clip");
    const double nearClip = hasClip ? p.getFloat("near_clip") : 0.0, farClip = hasClip ? p.getFloat("far_clip") : 0.0;

    std::vector<Setup> setups;
    Vector2i size = cam->film().fullSize();
    setups.push_back(setupOf(fmt::format("film {}×{}", size.x, size.y), cam));
    struct FilmShape {
        const char* label;
        int w, h, cx, cy, cw, ch;
    };
    if (t.hasParameter("film"))
        for (FilmShape f : {FilmShape{"wide film 64×8", 64, 8, 0, 0, 0, 0}, FilmShape{"tall film 6×80", 6, 80, 0, 0, 0, 0},
                            FilmShape{"film 1×1", 1, 1, 0, 0, 0, 0},
                            FilmShape{"film 120×90 cropped to 30,20 + 40×30", 120, 90, 30, 20, 40, 30}})
            setups.push_back(setupOf(f.label, query<ICamera>(t.create(
                                                  {{"film", ComponentValue{"film", makeFilm(reg, f.w, f.h, f.cx, f.cy, f.cw, f.ch)}}}))));

    checkRays(t, setups, nearClip, farClip, hasClip);
    if (!setups[0].imp) {
        t.skip("projection inverts generateRay", "the camera does not implement ICameraImportance");
        return;
    }
    checkInverse(t, setups);
    checkImportance(t, setups[0]);
    checkDirectionDensity(t, *setups[0].cam, *setups[0].imp);
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("camera",
                         "finite unit rays over the film, clip range, projection inverts generateRay, importance "
                         "matches the density of generated rays",
                         effigi::conform::runCameraSuite);

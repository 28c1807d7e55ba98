// The orthographic and thin-lens cameras, and the projection code they share with the
// perspective camera (components/camera/projection.hpp): parallel rays over the right
// world-space rectangle, a zero aperture that is exactly the pinhole, rays through one
// film point meeting on the focus plane, the focal_length parameter, parameter errors,
// and both cameras end to end against Mitsuba 3 on a small scene (tests/data/cameras).
#include "camera_helpers.hpp"
#include "image_helpers.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

using namespace effigi;

namespace {

using test::makeCamera;
using test::makeFilm;
using test::Params;
using test::rayAt;

const Point3f Eye(1.f, 2.f, 5.f), Target(0.f, 0.5f, 0.f);
const Vector3f Up(0.f, 1.f, 0.f);

} // namespace

TEST_CASE("orthographic: parallel rays covering the scaled film rectangle", "[camera][orthographic]") {
    // 60 x 40 film, scale (3, 2): Mitsuba's film rectangle is [-1, 1] x [-1/a, 1/a] in
    // camera units, so 6 x (4 / 1.5) world units here.
    const float sx = 3.f, sy = 2.f, nearClip = 0.5f, aspect = 60.f / 40.f;
    auto cam = makeCamera("orthographic", 60, 40,
                          {{"to_world", Transform::lookAt(Eye, Target, Up) * Transform::scale({sx, sy, 1.f})},
                           {"near_clip", double(nearClip)},
                           {"far_clip", 20.0}});
    Vector3f fwd = normalize(Target - Eye);
    Vector3f right = normalize(cross(fwd, Up));  // image right = camera −x
    Vector3f up = cross(right, fwd);
    Point3f centre = Eye + nearClip * fwd;
    for (float x : {0.f, 13.f, 30.f, 60.f})
        for (float y : {0.f, 7.5f, 20.f, 40.f}) {
            Ray r = rayAt(*cam, {x, y});
            INFO(x << " " << y);
            CHECK(length(r.d - fwd) < 1e-5f);  // all parallel to the viewing direction
            CHECK(r.tMax == Approx(20.f - nearClip));
            // Where on the near plane: (2x/W − 1) sx to the right, (1 − 2y/H) sy/a up.
            Point3f want = centre + ((2.f * x / 60.f - 1.f) * sx) * right + ((1.f - 2.f * y / 40.f) * sy / aspect) * up;
            CHECK(length(r.o - want) < 1e-4f);
        }
}

TEST_CASE("thinlens: zero aperture is the pinhole camera", "[camera][thinlens]") {
    Params common = {{"to_world", Transform::lookAt(Eye, Target, Up)}, {"fov", 35.0}, {"fov_axis", std::string("y")},
                     {"near_clip", 0.1}, {"far_clip", 50.0}};
    auto pin = makeCamera("perspective", 32, 24, common);
    Params tl = common;
    tl.push_back({"aperture_radius", 0.0});
    tl.push_back({"focus_distance", 3.0});
    auto lens = makeCamera("thinlens", 32, 24, tl);
    PCG32 rng(1, 2);
    for (int i = 0; i < 200; ++i) {
        Point2f film(32.f * rng.nextFloat(), 24.f * rng.nextFloat()), u(rng.nextFloat(), rng.nextFloat());
        Ray a = rayAt(*pin, film), b = rayAt(*lens, film, u);
        CHECK(length(a.o - b.o) < 1e-5f);
        CHECK(length(a.d - b.d) < 1e-5f);
        CHECK(a.tMax == Approx(b.tMax).epsilon(1e-5));
    }
}

TEST_CASE("thinlens: rays through one film point meet on the focus plane", "[camera][thinlens]") {
    const float focus = 4.f, aperture = 0.3f;
    auto lens = makeCamera("thinlens", 40, 30,
                           {{"to_world", Transform::lookAt(Eye, Target, Up)}, {"fov", 40.0},
                            {"aperture_radius", double(aperture)}, {"focus_distance", double(focus)}});
    auto pin = makeCamera("perspective", 40, 30, {{"to_world", Transform::lookAt(Eye, Target, Up)}, {"fov", 40.0}});
    Vector3f fwd = normalize(Target - Eye);
    PCG32 rng(3, 4);
    for (Point2f film : {Point2f(20.f, 15.f), Point2f(3.f, 27.f), Point2f(38.5f, 1.f)}) {
        // The pinhole ray through the same film point fixes the point in focus.
        Ray p = rayAt(*pin, film);
        Point3f inFocus = p.o + ((focus - dot(p.o - Eye, fwd)) / dot(p.d, fwd)) * p.d;
        double r2 = 0.0;
        const int N = 4000;
        for (int i = 0; i < N; ++i) {
            Ray r = rayAt(*lens, film, {rng.nextFloat(), rng.nextFloat()});
            CHECK(length(r.d) == Approx(1.f));
            float t = (focus - dot(r.o - Eye, fwd)) / dot(r.d, fwd);
            CHECK(length(r.o + t * r.d - inFocus) < 1e-4f * focus);
            // Back to the lens plane: a point on the aperture disk.
            float t0 = -dot(r.o - Eye, fwd) / dot(r.d, fwd);
            Vector3f onLens = r.o + t0 * r.d - Eye;
            CHECK(length(onLens) <= aperture * (1.f + 1e-4f));
            r2 += double(dot(onLens, onLens));
        }
        // Uniform on the disk: E[r²] = R²/2, standard deviation of r² is R²/√12 per
        // sample; accepted within 4 standard errors (significance about 6e-5), seeded.
        double R2 = double(aperture) * aperture;
        CHECK(std::abs(r2 / N - R2 / 2.0) < 4.0 * R2 / std::sqrt(12.0 * N));
    }
}

TEST_CASE("projection: focal_length and fov_axis", "[camera][thinlens]") {
    // 50 mm on 35 mm film spans the 43.27 mm diagonal: diagonal fov 2 atan(43.27 / 100).
    auto lens = makeCamera("thinlens", 30, 20, {{"aperture_radius", 0.0}, {"focal_length", std::string("50mm")}});
    auto dflt = makeCamera("thinlens", 30, 20, {{"aperture_radius", 0.0}});  // 50mm is the default
    float halfDiag = std::atan(std::sqrt(36.f * 36.f + 24.f * 24.f) / 100.f);
    for (auto* cam : {lens.get(), dflt.get()}) {
        Ray corner = rayAt(*cam, {0.f, 0.f});
        CHECK(std::acos(corner.d.z) == Approx(halfDiag).epsilon(1e-4));
    }
    // The perspective camera takes focal_length too (instead of its default fov).
    auto pin = makeCamera("perspective", 30, 20, {{"focal_length", std::string("35")}});
    CHECK(std::acos(rayAt(*pin, {0.f, 0.f}).d.z) ==
          Approx(std::atan(std::sqrt(36.f * 36.f + 24.f * 24.f) / 70.f)).epsilon(1e-4));
}

TEST_CASE("thinlens and orthographic: parameter errors name the parameter", "[camera][thinlens][orthographic]") {
    auto bad = [](const std::string& type, Params params, const std::string& needle) {
        INFO(type << " " << needle);
        try {
            makeCamera(type, 8, 8, params);
            FAIL("no error");
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find(needle) != std::string::npos);
            CHECK(std::string(e.what()).find('\n') == std::string::npos);
        }
    };
    bad("thinlens", {}, "aperture_radius");  // required, as in Mitsuba
    bad("thinlens", {{"aperture_radius", -0.1}}, "aperture_radius");
    bad("thinlens", {{"aperture_radius", 0.1}, {"focus_distance", 0.0}}, "focus_distance");
    bad("thinlens", {{"aperture_radius", 0.1}, {"fov", 30.0}, {"focal_length", std::string("50mm")}}, "focal_length");
    bad("thinlens", {{"aperture_radius", 0.1}, {"focal_length", std::string("wide")}}, "focal_length");
    bad("thinlens", {{"aperture_radius", 0.1}, {"fov", 180.0}}, "fov");
    bad("thinlens", {{"aperture_radius", 0.1}, {"to_world", Transform::scale({2.f, 2.f, 2.f})}}, "to_world");
    bad("thinlens", {{"aperture_radius", 0.1}, {"near_clip", 5.0}, {"far_clip", 1.0}}, "far_clip");
    bad("orthographic", {{"to_world", Transform::scale({1.f, 0.f, 1.f})}}, "to_world");
    bad("orthographic", {{"near_clip", 0.0}}, "near_clip");
}

namespace {

struct Region {
    const char* name;
    float x0, y0, x1, y1;
    double systematic;  ///< relative disagreement allowed beyond the noise
};

/// Renders tests/data/cameras/<name>.xml with effigi and compares region means of the grey
/// image with Mitsuba 3's 4096-spp reference of the same file.
void compareWithMitsuba(const std::string& name, std::vector<Region> regions) {
    xml::ParseOptions opt;
    opt.defines = {{"spp", "256"}};
    auto scene = loadSceneFile(EFFIGI_SOURCE_DIR "/tests/data/cameras/" + name + ".xml", opt);
    RenderControl control;
    control.progress = false;
    RenderStats stats = scene->renderer().render(*scene, control);
    CHECK(stats.rejectedSamples == 0);
    Image img = scene->camera().film().develop();
    test::ExrImage ref = test::readExr(EFFIGI_SOURCE_DIR "/tests/data/cameras/" + name + "-mitsuba.exr");
    REQUIRE(ref.spec.width == img.width);
    REQUIRE(ref.spec.height == img.height);
    int rc = ref.channel("R"), gc = ref.channel("G"), bc = ref.channel("B");
    REQUIRE(rc >= 0);
    auto ours = [&](int x, int y) { return (img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0; };
    auto theirs = [&](int x, int y) { return (ref.at(x, y, rc) + ref.at(x, y, gc) + ref.at(x, y, bc)) / 3.0; };

    // Regions as fractions of the image: the whole, the quadrants (the projection puts
    // each object in its own one), the centre, and those the caller adds.
    for (Region r : {Region{"image", 0, 0, 1, 1, 0.01}, Region{"top left", 0, 0, .5f, .5f, 0.02},
                     Region{"top right", .5f, 0, 1, .5f, 0.02}, Region{"bottom left", 0, .5f, .5f, 1, 0.02},
                     Region{"bottom right", .5f, .5f, 1, 1, 0.02}, Region{"centre", .33f, .33f, .67f, .67f, 0.02}})
        regions.push_back(r);
    for (const Region& r : regions) {
        int x0 = int(r.x0 * img.width), x1 = int(r.x1 * img.width), y0 = int(r.y0 * img.height),
            y1 = int(r.y1 * img.height);
        double a = 0, b = 0, d2 = 0;
        int n = 0, nd = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                a += ours(x, y);
                b += theirs(x, y);
                ++n;
                if (x + 2 < x1) {
                    double d = (ours(x, y) - theirs(x, y)) - (ours(x + 2, y) - theirs(x + 2, y));
                    d2 += d * d;
                    ++nd;
                }
            }
        a /= n;
        b /= n;
        // Our pixel noise from differences two pixels apart of ours − reference: the image
        // structure cancels in ours − reference (and what is left of a disagreement is
        // smooth, so it cancels between neighbours), the reference's noise (4096 spp) is
        // negligible, and with the box filter pixels are independent: σ² = ⟨Δ²⟩ / 2.
        double se = std::sqrt(d2 / (2.0 * nd) / n);
        // Tolerance: the region's systematic allowance (1 % image, 2 % region) plus 4
        // standard errors of our 256-spp estimate (two-sided false alarm 6e-5 per region;
        // the render is seeded). The reference's noise at 4096 spp is negligible.
        double rel = (a - b) / b, tol = r.systematic + 4.0 * se / b;
        INFO(name << " " << r.name << ": effigi " << a << " ± " << se << ", mitsuba " << b << ", relative " << rel
                  << ", tolerance " << tol);
        CHECK(std::abs(rel) < tol);
        CHECK(tol < 0.06);
    }
}

} // namespace

TEST_CASE("orthographic: renders like Mitsuba 3", "[camera][orthographic][render]") {
    compareWithMitsuba("orthographic", {});
}

TEST_CASE("thinlens: renders like Mitsuba 3", "[camera][thinlens][render]") {
    // The horizon behind the scene is far out of focus: its blurred band is where the
    // amount of defocus shows (an aperture 30 % too small moves its mean by 2.6 %, past
    // the ~2.4 % tolerance, while the other region means hardly change).
    compareWithMitsuba("thinlens", {{"defocused horizon", 8.f / 48, 20.f / 48, 44.f / 48, 24.f / 48, 0.01}});
}

// Cameras: the perspective camera's orientation conventions (Mitsuba's: image right is
// the camera's right, image top is up), field of view along each fov_axis choice,
// principal-point offset, ray properties, nested film/sampler and parameter errors.
#include "camera_helpers.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"

#include <catch2/catch.hpp>

using namespace effigi;

namespace {

using test::makeFilm;
using test::Params;

/// Camera at (0,0,3.9) looking at the origin with +y up (the Cornell box view).
Ref<ICamera> makeCamera(int w, int h, const Params& params = {}) {
    Params all = {{"to_world", Transform::lookAt({0.f, 0.f, 3.9f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f})}};
    all.insert(all.end(), params.begin(), params.end());
    return test::makeCamera("perspective", w, h, all);
}

Ray rayAt(const ICamera& cam, float x, float y) { return test::rayAt(cam, Point2f(x, y)); }

/// Angle (degrees) between a ray and the viewing axis −z.
float angleToAxis(const Ray& r) { return std::acos(std::clamp(-r.d.z, -1.f, 1.f)) * 180.f / Pi; }

float deg(float radians) { return radians * 180.f / Pi; }

} // namespace

TEST_CASE("perspective camera: orientation follows Mitsuba's conventions", "[camera]") {
    auto cam = makeCamera(64, 64, {{"fov", 60.0}});
    Ray centre = rayAt(*cam, 32.f, 32.f);
    CHECK(centre.o.x == Approx(0.f).margin(1e-6));
    CHECK(centre.o.z == Approx(3.9f - 0.01f));  // on the near plane (near_clip 0.01)
    CHECK(centre.d.x == Approx(0.f).margin(1e-6));
    CHECK(centre.d.y == Approx(0.f).margin(1e-6));
    CHECK(centre.d.z == Approx(-1.f));

    // Right edge: fov/2 off the axis, toward the camera's right, which is world +x for a
    // camera at +z looking down −z with +y up.
    Ray right = rayAt(*cam, 64.f, 32.f);
    CHECK(angleToAxis(right) == Approx(30.f).epsilon(1e-4));
    CHECK(right.d.x > 0.f);
    CHECK(right.d.y == Approx(0.f).margin(1e-6));

    // Top row looks up, bottom row down.
    Ray top = rayAt(*cam, 32.f, 0.f);
    CHECK(angleToAxis(top) == Approx(30.f).epsilon(1e-4));
    CHECK(top.d.y > 0.f);
    CHECK(rayAt(*cam, 32.f, 64.f).d.y < 0.f);
    CHECK(rayAt(*cam, 0.f, 32.f).d.x < 0.f);
}

TEST_CASE("perspective camera: rays are unit length and span the near to the far clip plane", "[camera]") {
    auto cam = makeCamera(40, 30, {{"near_clip", 0.5}, {"far_clip", 100.0}});
    Point3f eye = cam->toWorld().point(Point3f(0.f));
    for (float x : {0.f, 7.3f, 20.f, 40.f})
        for (float y : {0.f, 11.1f, 30.f}) {
            Ray r = rayAt(*cam, x, y);
            float cosAxis = -r.d.z;  // this camera looks along world −z
            CHECK(length(r.d) == Approx(1.f).epsilon(1e-6));
            // The origin lies on the near plane along the ray, the end on the far plane.
            CHECK(length(r.o - eye) * cosAxis == Approx(0.5f).epsilon(1e-5));
            CHECK(dot(normalize(r.o - eye), r.d) == Approx(1.f).epsilon(1e-6));
            CHECK((r.tMax * cosAxis + 0.5f) == Approx(100.f).epsilon(1e-5));
        }
}

TEST_CASE("perspective camera: fov applies to the chosen axis of a non-square film", "[camera]") {
    const float fov = 50.f, t = std::tan(degToRad(fov / 2));
    struct Case {
        int w, h;
        const char* axis;
        float right, top;  // expected half-angles (deg) at the right-edge and top-edge centres
    };
    // Wide film 200×100 (aspect 2) and tall film 100×200 (aspect ½).
    std::vector<Case> cases{
        {200, 100, "x", fov / 2, deg(std::atan(t / 2))},
        {200, 100, "y", deg(std::atan(t * 2)), fov / 2},
        {200, 100, "smaller", deg(std::atan(t * 2)), fov / 2},
        {200, 100, "larger", fov / 2, deg(std::atan(t / 2))},
        {100, 200, "x", fov / 2, deg(std::atan(t * 2))},
        {100, 200, "smaller", fov / 2, deg(std::atan(t * 2))},
        {100, 200, "larger", deg(std::atan(t / 2)), fov / 2},
    };
    for (const auto& c : cases) {
        INFO(c.w << "x" << c.h << " fov_axis " << c.axis);
        auto cam = makeCamera(c.w, c.h, {{"fov", double(fov)}, {"fov_axis", std::string(c.axis)}});
        CHECK(angleToAxis(rayAt(*cam, float(c.w), c.h / 2.f)) == Approx(c.right).epsilon(1e-4));
        CHECK(angleToAxis(rayAt(*cam, c.w / 2.f, 0.f)) == Approx(c.top).epsilon(1e-4));
    }
    // Diagonal: the corner is fov/2 off the axis.
    auto cam = makeCamera(200, 100, {{"fov", double(fov)}, {"fov_axis", std::string("diagonal")}});
    Ray corner = rayAt(*cam, 200.f, 0.f);
    CHECK(angleToAxis(corner) == Approx(fov / 2).epsilon(1e-4));
    CHECK(corner.d.x > 0.f);
    CHECK(corner.d.y > 0.f);
}

TEST_CASE("perspective camera: principal point offset shifts the image", "[camera]") {
    auto shifted = makeCamera(100, 50, {{"principal_point_offset_x", 0.25}, {"principal_point_offset_y", -0.1}});
    auto plain = makeCamera(100, 50);
    // An offset of (0.25, −0.1) film sizes moves the centre sample to where the plain
    // camera has pixel (75, 20).
    Ray a = rayAt(*shifted, 50.f, 25.f), b = rayAt(*plain, 75.f, 20.f);
    CHECK(length(a.d - b.d) < 1e-5f);
}

TEST_CASE("perspective camera: nested film and sampler, defaults", "[camera]") {
    auto film = makeFilm(32, 16);
    Properties sp("sampler", "independent");
    sp.set("sample_count", std::int64_t(16));
    auto sampler = Registry::instance().create("sampler", "independent", sp);
    Properties p("camera", "perspective");
    p.set("film", ComponentValue{"film", film});
    p.set("sampler", ComponentValue{"sampler", sampler});
    auto cam = query<ICamera>(Registry::instance().create("camera", "perspective", p));
    REQUIRE(cam);
    CHECK(&cam->film() == film.get());
    CHECK(cam->sampler().samplesPerPixel() == 16);
    // Identity to_world: looks along +z, image right is local −x.
    Ray r = rayAt(*cam, 32.f, 8.f);
    CHECK(r.d.x < 0.f);
    // Default lens 50mm: tan(half diagonal fov) = √(36² + 24²) / 100, split W : H = 2 : 1.
    float halfX = std::sqrt(36.f * 36.f + 24.f * 24.f) / 100.f * 2.f / std::sqrt(5.f);
    CHECK(angleToAxis(Ray{r.o, -r.d, r.tMax}) == Approx(deg(std::atan(halfX))).epsilon(1e-4));

    // Everything defaulted: an hdrfilm and an independent sampler.
    Properties d("camera", "perspective");
    auto def = query<ICamera>(Registry::instance().create("camera", "perspective", d));
    REQUIRE(def);
    CHECK(def->film().size().x > 0);
    CHECK(def->sampler().samplesPerPixel() == 4);
}

TEST_CASE("perspective camera: bad parameters are errors", "[camera]") {
    CHECK_THROWS_AS(makeCamera(10, 10, {{"fov", 0.0}}), Error);
    CHECK_THROWS_AS(makeCamera(10, 10, {{"fov", 180.0}}), Error);
    CHECK_THROWS_AS(makeCamera(10, 10, {{"fov", 200.0}}), Error);
    CHECK_THROWS_AS(makeCamera(10, 10, {{"fov_axis", std::string("z")}}), Error);
    CHECK_THROWS_AS(makeCamera(10, 10, {{"near_clip", 5.0}, {"far_clip", 1.0}}), Error);
    CHECK_THROWS_AS(makeCamera(10, 10, {{"near_clip", 0.0}}), Error);
    Properties p("camera", "perspective");
    p.set("to_world", Transform::scale({2.f, 2.f, 2.f}));
    CHECK_THROWS_WITH(Registry::instance().create("camera", "perspective", p), Catch::Contains("to_world"));
}

TEST_CASE("perspective camera: without fov or focal_length it is a 50mm lens on the diagonal (Mitsuba 3)", "[camera]") {
    // Mitsuba 3's projective cameras default to focal_length "50mm": the diagonal field of
    // view of 35 mm film (36 x 24 mm), 2·atan(√(36² + 24²) / 100) ≈ 46.79°.
    auto byDefault = makeCamera(64, 64, {});
    auto lens = makeCamera(64, 64, {{"focal_length", std::string("50mm")}});
    auto diag = makeCamera(64, 64, {{"fov", 46.7930}, {"fov_axis", std::string("diagonal")}});
    for (Point2f p : {Point2f(0.f, 0.f), Point2f(64.f, 32.f), Point2f(10.f, 50.f)}) {
        Vector3f a = rayAt(*byDefault, p.x, p.y).d, b = rayAt(*lens, p.x, p.y).d, c = rayAt(*diag, p.x, p.y).d;
        for (int k = 0; k < 3; ++k) {
            CHECK(a[k] == Approx(b[k]).margin(1e-6));
            CHECK(a[k] == Approx(c[k]).margin(1e-4));
        }
    }
}

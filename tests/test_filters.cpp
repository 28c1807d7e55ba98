// Reconstruction filters and ImageBlock splatting: filter kernels (shape, published
// values, the tabulated kernel), block borders and clipping, and how much weight one
// sample deposits wherever it lands.
#include "film_helpers.hpp"

#include "effigi/math/rng.hpp"
#include "effigi/render/image_block.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace effigi;
using namespace effigi::test;

namespace {

const std::vector<std::string> FilterNames{"box", "gaussian", "tent", "mitchell", "lanczos"};

/// Total splatted weight of a block: the sum of its weight channel.
float weightSum(const ImageBlock& b) {
    float sum = 0.f;
    for (std::size_t i = std::size_t(b.channels()); i < b.data().size(); i += std::size_t(b.stride())) sum += b.data()[i];
    return sum;
}

} // namespace

TEST_CASE("box filter block touches exactly the pixel containing the sample", "[film]") {
    FilterTable table(*makeFilter("box"));
    ImageBlock block({0, 0}, {8, 8}, 1, &table);
    CHECK(block.border() == 0);
    const float value = 2.f;
    for (Point2f pos : {Point2f(3.3f, 4.7f), Point2f(3.f, 4.f), Point2f(3.999f, 4.999f)}) {
        block.clear();
        block.put(pos, &value);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const float* px = block.pixel(x, y);
                bool inside = x == 3 && y == 4;
                CHECK(px[0] == (inside ? 2.f : 0.f));
                CHECK(px[1] == (inside ? 1.f : 0.f));
            }
    }
    // Outside the block, NaN or infinite: nothing is touched and nothing crashes.
    block.clear();
    for (Point2f pos : {Point2f(-5.f, 3.f), Point2f(100.f, 1e30f), Point2f(NAN, 2.f), Point2f(2.f, INFINITY)})
        block.put(pos, &value);
    CHECK(weightSum(block) == 0.f);
}

TEST_CASE("block border is ceil(radius - 0.5) and storage holds channels + weight", "[film]") {
    const std::vector<std::pair<std::string, int>> expected{
        {"box", 0}, {"tent", 1}, {"gaussian", 2}, {"mitchell", 2}, {"lanczos", 3}};
    for (const auto& [name, border] : expected) {
        FilterTable table(*makeFilter(name));
        ImageBlock block({5, 7}, {4, 3}, 2, &table);
        INFO(name);
        CHECK(block.border() == border);
        CHECK(block.stride() == 3);
        CHECK(block.data().size() == std::size_t((4 + 2 * border) * (3 + 2 * border) * 3));
        // The border is wide enough: a sample anywhere inside the block, even at its
        // corners, deposits its full weight (the kernel summed over all pixel centres
        // in reach), none of it clipped.
        Ref<IFilter> f = makeFilter(name);
        auto lattice = [&](float p) {  // pixel centres c with p - r < c <= p + r
            float s = 0.f;
            for (int k = -40; k <= 40; ++k) {
                float d = std::floor(p) + float(k) + 0.5f - p;
                if (d > -f->radius() && d <= f->radius()) s += f->eval(d);
            }
            return s;
        };
        const float v[2] = {1.f, 1.f};
        for (Point2f p : {Point2f(5.f, 7.f), Point2f(8.999f, 9.999f), Point2f(5.001f, 9.9f), Point2f(7.5f, 8.5f)}) {
            block.clear();
            block.put(p, v);
            CHECK(weightSum(block) == Approx(lattice(p.x) * lattice(p.y)).epsilon(1e-3));
        }
        // Samples beyond the block are clipped, not written out of bounds.
        for (int k = 0; k < 400; ++k) block.put(Point2f(-2.f + 0.05f * float(k), 3.f + 0.03f * float(k)), v);
    }
}

TEST_CASE("filters are symmetric, positive at the centre and zero beyond the radius", "[film]") {
    for (const std::string& name : FilterNames) {
        INFO(name);
        Ref<IFilter> f = makeFilter(name);
        const float r = f->radius();
        CHECK(r > 0.f);
        CHECK(f->eval(0.f) > 0.f);
        for (int i = 0; i <= 300; ++i) {
            float x = 1.5f * r * float(i) / 300.f;
            CHECK(f->eval(x) == f->eval(-x));
            if (x > r) CHECK(f->eval(x) == 0.f);
        }
        CHECK(f->eval(r * 1.0001f) == 0.f);
        CHECK(f->eval(1e6f) == 0.f);
        // The table interpolates the kernel linearly between 1/64-pixel knots: error
        // <= h^2/8 max|k''| ~ 1e-4 (the box's step sits exactly at a knot).
        FilterTable table(*f);
        for (int i = 0; i < 200; ++i) {
            float x = r * float(i) / 200.f;
            CHECK(table(x) == Approx(f->eval(x)).margin(1e-3));
            CHECK(table(-x) == table(x));
        }
        CHECK(table(r * 1.01f) == 0.f);
    }
}

TEST_CASE("filter kernels take their published values", "[film]") {
    // Gaussian (sigma 0.5, radius 2): exp(-x^2/(2 sigma^2)) - exp(-8).
    Ref<IFilter> g = makeFilter("gaussian");
    CHECK(g->radius() == Approx(2.f));
    CHECK(g->eval(0.f) == Approx(1.f - std::exp(-8.f)));
    CHECK(g->eval(0.5f) == Approx(std::exp(-0.5f) - std::exp(-8.f)));
    // Tent (radius 1) and box.
    CHECK(makeFilter("tent")->eval(0.25f) == Approx(0.75f));
    CHECK(makeFilter("box")->eval(0.5f) == 1.f);
    CHECK(makeFilter("box")->eval(0.51f) == 0.f);
    // Mitchell-Netravali with B = C = 1/3: k(0) = (6 - 2B)/6, k(1) = B/6.
    Ref<IFilter> m = makeFilter("mitchell");
    CHECK(m->radius() == 2.f);
    CHECK(m->eval(0.f) == Approx((6.f - 2.f / 3.f) / 6.f));
    CHECK(m->eval(1.f) == Approx(1.f / 18.f));
    // Lanczos: 1 at the centre, zeros at the other integers, radius = lobes.
    Ref<IFilter> l = makeFilter("lanczos");
    CHECK(l->radius() == 3.f);
    CHECK(l->eval(0.f) == Approx(1.f));
    CHECK(l->eval(1.f) == Approx(0.f).margin(1e-6));
    CHECK(l->eval(2.f) == Approx(0.f).margin(1e-6));
    // Tent, Mitchell-Netravali and Lanczos (at integer spacing) reproduce a constant:
    // their weights at unit spacing sum to 1 wherever the sample lies.
    for (const char* name : {"tent", "mitchell"}) {
        Ref<IFilter> f = makeFilter(name);
        for (float u : {0.f, 0.1f, 0.37f, 0.5f, 0.81f}) {
            float sum = 0.f;
            for (int k = -4; k <= 4; ++k) sum += f->eval(float(k) + u);
            INFO(name << " u=" << u);
            CHECK(sum == Approx(1.f).margin(1e-5));
        }
    }
}

TEST_CASE("splatted weight is nearly independent of where the sample lands", "[film]") {
    // The block's total weight is the separable product of the kernel summed over the
    // pixel centres in x and in y. For the Gaussian of sigma 0.5 each sum ripples by
    // about 2 exp(-2 pi^2 sigma^2) = +-1.4% with the sample position (Poisson summation)
    // around its integral sigma sqrt(2 pi) erf(...) - 4 exp(-8), so the 2D total spans
    // ~5.6% and stays within 3% of the squared integral; the tabulated kernel adds <0.1%.
    Ref<IFilter> g = makeFilter("gaussian");
    FilterTable gauss(*g);
    ImageBlock block({0, 0}, {16, 16}, 1, &gauss);
    const float one = 1.f;
    const float integral = 0.5f * std::sqrt(2.f * Pi) * std::erf(2.f * std::sqrt(2.f)) - 4.f * std::exp(-8.f);
    auto lattice = [&](float u) {  // sum of the exact kernel over the pixel centres
        float s = 0.f;
        for (int k = -3; k <= 3; ++k) s += g->eval(float(k) + 0.5f - u);
        return s;
    };
    float lo = Infinity, hi = 0.f, mean = 0.f;
    PCG32 rng(11, 2);
    for (int k = 0; k < 300; ++k) {
        // Half the positions on a 1/16 grid (aligned with the table's bins), half random.
        float u = k < 150 ? float(k % 16) / 16.f : rng.nextFloat();
        float v = k < 150 ? float(k / 16) / 16.f : rng.nextFloat();
        block.clear();
        block.put(Point2f(7.f + u, 8.f + v), &one);
        const float w = weightSum(block);
        lo = std::min(lo, w), hi = std::max(hi, w), mean += w / 300.f;
        CHECK(w == Approx(lattice(u) * lattice(v)).epsilon(1e-3));
        CHECK(w == Approx(integral * integral).epsilon(0.03));
    }
    CHECK(mean == Approx(integral * integral).epsilon(0.01));
    CHECK((hi - lo) / hi < 0.06f);

    // Box and tent form partitions of unity: the total is 1 (tent: up to rounding).
    for (const char* name : {"box", "tent"}) {
        FilterTable table(*makeFilter(name));
        ImageBlock b({0, 0}, {8, 8}, 1, &table);
        PCG32 rng(7, 1);
        for (int k = 0; k < 100; ++k) {
            b.clear();
            b.put(Point2f(2.f + 4.f * rng.nextFloat(), 2.f + 4.f * rng.nextFloat()), &one);
            INFO(name);
            CHECK(weightSum(b) == Approx(1.f).margin(1e-5));
        }
    }
}

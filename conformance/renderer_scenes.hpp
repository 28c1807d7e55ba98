#pragma once
// Scenes of the renderer suite (conformance/renderer_suite.cpp) whose pixels have exact
// values, and what the suite knows of the renderer that renders them.
//
// Every scene is spectrally flat (float reflectances, one emission spectrum), and every
// pixel sees the same radiance: a multiple of the emitted radiance Le, the multiple
// depending only on the reflectance, the path depth the renderer is limited to (Mitsuba's
// max_depth: 1 = emitters seen directly, 2 = direct lighting, −1 = unbounded) and whether
// it hides emitters seen directly. So the exact image mean is that multiple of the colour
// the film gives Le, which emittedGrey() integrates over wavelengths.
#include "conformance/conformance.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/scene.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace effigi::conform {

/// What a renderer computes, as far as the scenes' exact values depend on it.
struct Semantics {
    int depth = -1;             ///< Mitsuba's max_depth; −1: unbounded
    bool hideEmitters = false;  ///< emitters seen directly by the camera are hidden
};

struct AnalyticScene {
    std::string name;
    bool environment = false;  ///< lit by a constant environment (else by area emitters)
    /// The shapes and emitters (XML).
    std::string body;
    /// The camera: look from `origin` at `target` (up +y), horizontal field of view in degrees.
    std::string origin, target;
    double fov = 30.0;
    /// The exact pixel value as a multiple of the emitted radiance; none where it has no
    /// closed form (the reason then in `why`).
    std::function<std::optional<double>(const Semantics&)> exact;
    std::string why;
    /// Fraction of the scene's surface area the camera sees (radiosity's error bound is an
    /// area-weighted mean over all of it).
    double seenArea = 1.0;
    /// Renderers that sample paths are held to this scene only up to this max_depth
    /// (−1: any), for the reason in `stochasticWhy`.
    int stochasticDepth = -1;
    std::string stochasticWhy;
};

/// The cameras' near clip distance (Mitsuba's default): rays start there.
constexpr double NearClip = 0.01;

/// The scenes, from the cheapest; --quick leaves out the intermediate reflectance.
std::vector<AnalyticScene> analyticScenes(bool quick);

/// The scene with a res × res film (box filter: pixels are independent estimates) and an
/// independent sampler taking spp samples per pixel.
std::unique_ptr<Scene> loadAnalytic(const AnalyticScene& s, int res, int spp);

/// The film's expected grey (R + G + B)/3 (linear sRGB) of the radiance the scene's
/// emitters emit: the wavelength integral of cie::toXYZ over SampledWavelengths::
/// sampleVisible by the midpoint rule on 2¹⁴ points (error far below 1e-6).
double emittedGrey(const Scene& scene);

/// Per-pixel grey (R + G + B)/3 of a developed image's colour channels; empty when the
/// image has no "R", "G", "B".
std::vector<double> greyPixels(const Image& image);

} // namespace effigi::conform

#pragma once
// RenderMan RIB scenes: `effigi render scene.rib` (loadSceneFile dispatches on the .rib
// extension). A translator, not a second scene system: the RIB requests are interpreted
// (src/rib/interpreter.cpp: RenderMan's graphics state, its attribute and transform
// stacks) into effigi elements, the same xml::Node elements the XML parser makes, each
// located at its RIB file:line, and those are created by the XML loader's
// instantiate(); polygons, patches and the quadrics effigi has no shape for become
// triangle meshes handed to MeshShape directly. Errors are one line,
// "file:line: RIB request 'X' ...", and effigi::Error like every other input error.
//
// Supported (docs/rib.md has the full table and the mapping of each request):
//   structure   FrameBegin/End, WorldBegin/End, AttributeBegin/End, TransformBegin/End
//   transforms  Identity, Transform, ConcatTransform, Translate, Rotate, Scale
//   camera      Projection "perspective" ("fov") | "orthographic", Format, Clipping,
//               PixelSamples (samples per pixel = xs·ys, else 64; -D spp=N overrides),
//               Display (accepted; the output is the CLI's -o)
//   shading     Color, Opacity, Surface "matte" | "plastic" | "metal",
//               LightSource "pointlight" | "distantlight" | "ambientlight"
//   geometry    Sphere, Cylinder, Cone, Disk, Polygon, GeneralPolygon, PointsPolygons,
//               PointsGeneralPolygons (one loop per polygon), Patch "bilinear" |
//               "bicubic", Basis
//   ignored     version, Option, Attribute, Declare, ShadingRate, ShadingInterpolation,
//               Sides, Orientation, ReverseOrientation, Bound, Detail, DetailRange,
//               PixelFilter, Quantize, Hider
// Request names match without regard to case, and the pre-3.1 names `light` and
// `gpolygon` (Firebaugh's example) are read as LightSource and GeneralPolygon.
//
// Handedness: RenderMan's camera space is left-handed (x right, y up, z into the
// screen); effigi's (Mitsuba's) is right-handed with x to the left. The world keeps the
// RIB's coordinates, and the camera's to_world is the inverse of the world-to-camera
// transformation followed by the mirror x -> -x, so that a point that RenderMan shows on
// the right of the image is on the right here too.
// Reference: Pixar, The RenderMan Interface, version 3.2 (2000).
#include "effigi/core/registry.hpp"
#include "effigi/render/scene.hpp"
#include "effigi/xml/parser.hpp"

#include <filesystem>
#include <memory>
#include <string>

namespace effigi::rib {

/// True for a file name ending in .rib (any case).
bool isRibFile(const std::filesystem::path& path);

/// Reads and builds a RIB scene. `opt.defines` may hold only spp (samples per pixel).
std::unique_ptr<Scene> loadFile(const std::filesystem::path& path, const xml::ParseOptions& opt = {},
                                Registry& registry = Registry::instance());
/// The same from text; `filename` names it in errors.
std::unique_ptr<Scene> loadString(const std::string& text, const std::string& filename,
                                  const xml::ParseOptions& opt = {}, Registry& registry = Registry::instance());

} // namespace effigi::rib

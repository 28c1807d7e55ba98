#pragma once
// The control-point files of Mitsuba's curve shapes (linearcurve, bsplinecurve): one point
// "x y z radius" per line, a blank line starts a new curve; positions go through to_world,
// radii do not (Mitsuba 3 documentation, "Linear curve").
#include "effigi/core/input.hpp"
#include "effigi/math/transform.hpp"

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace effigi::curves {

struct ControlPoint {
    Vector3d p;  ///< world space (to_world applied)
    double r;    ///< radius, not transformed
};

/// Control points of every curve in a file; curve k spans [first[k], first[k+1]).
struct CurveFile {
    std::vector<ControlPoint> points;
    std::vector<std::uint32_t> first;
};

/// Reads Mitsuba's curve format: one control point "x y z radius" per line, a blank line
/// starts a new curve. Errors name file:line. Every curve needs at least minPoints points.
inline CurveFile readCurveFile(const std::string& file, const Transform& toWorld, std::size_t minPoints,
                               const char* kind) {
    std::ifstream in(file);
    if (!in) fail("{}: cannot open {} file", file, kind);
    CurveFile f;
    std::string line;
    int lineNo = 0, curveLine = 0;
    bool open = false;  // a curve is being read
    const char* space = " \t\r\f\v";
    auto close = [&]() {
        if (open && f.points.size() - f.first.back() < minPoints)
            failAt({file, curveLine}, "{} needs at least {} control points per curve, this one has {}", kind,
                   minPoints, f.points.size() - f.first.back());
        open = false;
    };
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.find_first_not_of(space) == std::string::npos) {
            close();
            continue;
        }
        double v[4];
        const char* cur = line.c_str();
        for (double& x : v) {
            char* end;
            x = std::strtod(cur, &end);
            if (end == cur) failAt({file, lineNo}, "expected 4 numbers 'x y z radius', got '{}'", excerpt(line));
            cur = end;
        }
        if (std::string(cur).find_first_not_of(space) != std::string::npos)
            failAt({file, lineNo}, "unexpected text after 'x y z radius': '{}'", excerpt(line));
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
            failAt({file, lineNo}, "control point position is not finite");
        if (!(v[3] >= 0.0) || !std::isfinite(v[3]))
            failAt({file, lineNo}, "radius must be a finite number >= 0, got {}", v[3]);
        Point3f p = toWorld.point(Point3f(float(v[0]), float(v[1]), float(v[2])));
        if (!isFinite(p)) failAt({file, lineNo}, "control point is not finite after 'to_world'");
        if (!open) f.first.push_back(std::uint32_t(f.points.size())), curveLine = lineNo, open = true;
        f.points.push_back({Vector3d(p), v[3]});
    }
    close();
    if (f.points.empty()) failAt({file, 0}, "{} file contains no control points", kind);
    f.first.push_back(std::uint32_t(f.points.size()));
    return f;
}

} // namespace effigi::curves

// Mesh attributes from a PLY element's extra scalar properties, named as Mitsuba 3's PLY
// loader names them: colours r g b or red green blue -> "<element>_color"; groups
// prefix_{x,y,z}, prefix_{r,g,b}, prefix_{0,1,2}, prefix_{1,2,3} or a single prefix_x ->
// "<element>_<prefix>", "_color" appended for the r g b group. Integer values are
// normalised to [0, 1].
#include "ply_format.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"

#include <cstring>

namespace effigi::ply {

/// Integer attribute values divided by the type's largest value (uchar colours 0-255
/// -> [0, 1]). Mitsuba 3.9 keeps the raw integers and warns that colours are expected
/// in [0, 1]; scaling is what such files mean. No sRGB decoding: PLY does not say.
double normalizedInteger(Type t, double v) {
    double top = 1.0;
    switch (t) {
    case Type::I8: top = 127.0; break;
    case Type::U8: top = 255.0; break;
    case Type::I16: top = 32767.0; break;
    case Type::U16: top = 65535.0; break;
    case Type::I32: top = 2147483647.0; break;
    case Type::U32: top = 4294967295.0; break;
    case Type::I64: top = 9223372036854775807.0; break;
    case Type::U64: top = 18446744073709551615.0; break;
    default: return v;
    }
    return v / top;
}

std::vector<AttrGroup> attributeGroups(const Element& e, const std::string& prefix, std::vector<bool> taken,
                                       const std::string& fileName) {
    std::vector<AttrGroup> groups;
    auto find = [&](const char* n) -> int {
        for (std::size_t k = 0; k < e.props.size(); ++k)
            if (!taken[k] && !e.props[k].list && e.props[k].name == n) return int(k);
        return -1;
    };
    int r = find("r"), g = find("g"), b = find("b");
    if (r < 0 || g < 0 || b < 0) r = find("red"), g = find("green"), b = find("blue");
    if (r >= 0 && g >= 0 && b >= 0) {
        groups.push_back({prefix + "color", {std::size_t(r), std::size_t(g), std::size_t(b)}});
        taken[r] = taken[g] = taken[b] = true;
        // An alpha channel is read past: effigi keeps RGB colours only.
        for (const char* a : {"a", "alpha"})
            if (int k = find(a); k >= 0) taken[k] = true;
    }
    // Channel suffixes by position (rows) for each naming scheme (columns).
    static const char* const suffix[4] = {"xr01", "yg12", "zb23", "wa34"};
    AttrGroup cur;
    std::string curPrefix;
    int scheme = -1;
    auto flush = [&] {
        if (scheme < 0) return;
        bool dup = false;
        for (const AttrGroup& o : groups) dup = dup || o.name == cur.name;
        if ((cur.props.size() == 1 || cur.props.size() == 3) && !dup) groups.push_back(cur);
        else log::warn("{}: PLY attribute '{}' ignored ({})", fileName, excerpt(cur.name),
                       dup ? "given twice" : "1 or 3 channels are supported");
        scheme = -1;
    };
    for (std::size_t k = 0; k < e.props.size(); ++k) {
        if (taken[k] || e.props[k].list) continue;
        const std::string& n = e.props[k].name;
        std::size_t us = n.rfind('_');
        if (us == std::string::npos || us == 0 || us + 2 != n.size()) {
            flush();
            log::warn("{}: PLY {} property '{}' ignored (attributes are named <prefix>_<x|r|0|1>)", fileName,
                      excerpt(e.name), excerpt(n));
            continue;
        }
        std::string p = n.substr(0, us);
        char c = n[us + 1];
        if (scheme >= 0 && p != curPrefix) flush();
        if (scheme < 0) {
            const char* at = std::strchr(suffix[0], c);
            if (!at || c == '\0') {
                log::warn("{}: PLY {} property '{}' ignored (first channel must end in _x, _r, _0 or _1)", fileName,
                          excerpt(e.name), excerpt(n));
                continue;
            }
            scheme = int(at - suffix[0]);
            curPrefix = p;
            cur = {prefix + p + (scheme == 1 ? "_color" : ""), {k}};
        } else if (cur.props.size() < 4 && suffix[cur.props.size()][scheme] == c) {
            cur.props.push_back(k);
        } else {
            log::warn("{}: PLY attribute '{}' ignored (channel '{}' out of sequence)", fileName, excerpt(cur.name),
                      excerpt(n));
            scheme = -1;
        }
    }
    flush();
    return groups;
}

} // namespace effigi::ply

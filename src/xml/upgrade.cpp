// Version < 3 scene files. Mitsuba 3 converts camelCase parameter names of old files
// to snake_case; effigi does the same, and keeps a table for the names whose Mitsuba 3
// spelling is not the mechanical one (or whose mechanical form is easy to get wrong),
// written down here so that each is tested (tests/test_xml_compat.cpp).
#include "upgrade.hpp"

#include <array>
#include <cctype>
#include <utility>

namespace effigi::xml::detail {

namespace {

using Rename = std::pair<std::string_view, std::string_view>;

// Mitsuba 0.5/0.6 parameter names -> Mitsuba 3. The mechanical rule would give most of
// them too; listing the common ones pins them down, and the others need the table:
// renamed parameters (highQualityEdges, densityMultiplier) and acronyms (intIOR).
constexpr std::array kNames = {
    Rename{"toWorld", "to_world"},
    Rename{"toUV", "to_uv"},
    Rename{"sampleCount", "sample_count"},
    Rename{"maxDepth", "max_depth"},
    Rename{"rrDepth", "rr_depth"},
    Rename{"hideEmitters", "hide_emitters"},
    Rename{"strictNormals", "strict_normals"},
    Rename{"emitterSamples", "emitter_samples"},
    Rename{"bsdfSamples", "bsdf_samples"},
    Rename{"intIOR", "int_ior"},
    Rename{"extIOR", "ext_ior"},
    Rename{"extEta", "ext_eta"},
    Rename{"fovAxis", "fov_axis"},
    Rename{"nearClip", "near_clip"},
    Rename{"farClip", "far_clip"},
    Rename{"focusDistance", "focus_distance"},
    Rename{"apertureRadius", "aperture_radius"},
    Rename{"focalLength", "focal_length"},
    Rename{"shutterOpen", "shutter_open"},
    Rename{"diffuseReflectance", "diffuse_reflectance"},
    Rename{"specularReflectance", "specular_reflectance"},
    Rename{"specularTransmittance", "specular_transmittance"},
    Rename{"specularSamplingWeight", "specular_sampling_weight"},
    Rename{"alphaU", "alpha_u"},
    Rename{"alphaV", "alpha_v"},
    Rename{"sampleVisible", "sample_visible"},
    Rename{"flipNormals", "flip_normals"},
    Rename{"faceNormals", "face_normals"},
    Rename{"flipTexCoords", "flip_tex_coords"},
    Rename{"shapeIndex", "shape_index"},
    Rename{"samplingWeight", "sampling_weight"},
    Rename{"cutoffAngle", "cutoff_angle"},
    Rename{"beamWidth", "beam_width"},
    Rename{"pixelFormat", "pixel_format"},
    Rename{"componentFormat", "component_format"},
    Rename{"fileFormat", "file_format"},
    Rename{"cropOffsetX", "crop_offset_x"},
    Rename{"cropOffsetY", "crop_offset_y"},
    Rename{"cropWidth", "crop_width"},
    Rename{"cropHeight", "crop_height"},
    // hdrfilm: Mitsuba 3 calls the option sample_border.
    Rename{"highQualityEdges", "sample_border"},
    Rename{"filterType", "filter_type"},
    Rename{"wrapMode", "wrap_mode"},
    Rename{"maxAnisotropy", "max_anisotropy"},
    Rename{"sigmaA", "sigma_a"},
    Rename{"sigmaS", "sigma_s"},
    Rename{"sigmaT", "sigma_t"},
    // homogeneous medium: Mitsuba 3 calls the density multiplier `scale`.
    Rename{"densityMultiplier", "scale"},
    Rename{"sunScale", "sun_scale"},
    Rename{"skyScale", "sky_scale"},
    Rename{"sunRadiusScale", "sun_radius_scale"},
};

// Element names: Mitsuba 0.6 wrote the look-at transform operation in camelCase.
constexpr std::array kTags = {Rename{"lookAt", "lookat"}};

} // namespace

std::string upgradeTag(std::string_view tag) {
    for (const auto& [from, to] : kTags)
        if (tag == from) return std::string(to);
    return std::string(tag);
}

std::string upgradeAttribute(const std::string& tag, std::string_view attr) {
    // Mitsuba 0.6: <blackbody temperature="..." multiplier="..."/>.
    if (tag == "blackbody" && attr == "multiplier") return "scale";
    return std::string(attr);
}

std::string upgradeName(const std::string& name) {
    for (const auto& [from, to] : kNames)
        if (name == from) return std::string(to);
    return camelToSnake(name);
}

void upgradeFromV1(Node& node) {
    Properties& p = node.props;
    if (node.tag == "bsdf" && node.type == "diffuse" && p.has("diffuse_reflectance") && !p.has("reflectance")) {
        Properties::Entry e = *p.find("diffuse_reflectance");
        p.remove("diffuse_reflectance");
        p.set("reflectance", std::move(e.value), e.where);
    }
    // uoffset/voffset/uscale/vscale -> to_uv = scale * translate, as Mitsuba 3 does.
    const char* keys[4] = {"uoffset", "voffset", "uscale", "vscale"};
    bool any = false;
    for (const char* k : keys) any = any || p.has(k);
    if (!any || p.has("to_uv")) return;
    float v[4] = {0.f, 0.f, 1.f, 1.f};
    SourceLocation where = node.where;
    for (int i = 0; i < 4; ++i) {
        if (!p.has(keys[i])) continue;
        where = p.whereOf(keys[i]);
        v[i] = p.getFloat(keys[i]);
        p.remove(keys[i]);
    }
    if (v[2] == 0.f || v[3] == 0.f) failAt(where, "{}: a zero uscale/vscale makes to_uv singular", p.describe());
    p.set("to_uv", Transform::scale(Vector3f(v[2], v[3], 1.f)) * Transform::translate(Vector3f(v[0], v[1], 0.f)),
          where);
}

} // namespace effigi::xml::detail

namespace effigi::xml {

std::string camelToSnake(const std::string& name) {
    std::string out;
    auto upper = [](char c) { return std::isupper(static_cast<unsigned char>(c)) != 0; };
    auto lowerOrDigit = [](char c) {
        return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c));
    };
    for (std::size_t i = 0; i < name.size(); ++i) {
        char c = name[i];
        if (upper(c) && i > 0) {
            // A word starts at an upper-case letter after a lower-case one ("maxDepth"), or at
            // the last capital of an acronym followed by lower case ("HDRFilm" -> "hdr_film").
            bool boundary = lowerOrDigit(name[i - 1]) ||
                            (upper(name[i - 1]) && i + 1 < name.size() && std::islower(static_cast<unsigned char>(name[i + 1])));
            if (boundary && out.back() != '_') out += '_';
        }
        out += char(std::tolower(static_cast<unsigned char>(c)));
    }
    return out;
}

} // namespace effigi::xml

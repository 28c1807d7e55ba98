// Attribute text -> typed values for the XML parser. Everything here is strict: the
// whole text must parse, numbers must be finite and fit a float (the renderer computes
// in float, so 1e300 would silently become infinity), and every error names the file,
// line, element and attribute.
#include "values.hpp"

#include "effigi/core/input.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

namespace effigi::xml::detail {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

/// Whole-string number; false when the text is not one number.
bool toDouble(std::string_view s, double& out) {
    s = trim(s);
    if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
    if (s.empty()) return false;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && ptr == s.data() + s.size();
}

/// A finite number in float range, or an error worded by `what` ("attribute 'value'").
double checkedNumber(const Element& e, std::string_view what, std::string_view text) {
    double v = 0;
    if (!toDouble(text, v)) e.fail("{}: cannot parse '{}' as a number", what, excerpt(trim(text)));
    if (!std::isfinite(v)) e.fail("{}: '{}' is not a finite number", what, excerpt(trim(text)));
    if (std::abs(v) > double(std::numeric_limits<float>::max()))
        e.fail("{}: {} is out of the float range", what, excerpt(trim(text)));
    return v;
}

/// Split at commas and white space; an empty entry between two commas is an error.
std::vector<std::string_view> tokens(const Element& e, std::string_view attr, std::string_view text) {
    std::vector<std::string_view> out;
    if (trim(text).empty()) return out;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t comma = text.find(',', start);
        std::string_view piece = text.substr(start, comma == std::string_view::npos ? text.npos : comma - start);
        if (trim(piece).empty()) e.fail("attribute '{}': empty entry in '{}'", attr, excerpt(text));
        // Within a comma-separated piece, white space separates further entries.
        std::size_t i = 0;
        while (i < piece.size()) {
            while (i < piece.size() && std::isspace(static_cast<unsigned char>(piece[i]))) ++i;
            std::size_t j = i;
            while (j < piece.size() && !std::isspace(static_cast<unsigned char>(piece[j]))) ++j;
            if (j > i) out.push_back(piece.substr(i, j - i));
            i = j;
        }
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    return out;
}

Vector3f triple(const Element& e, std::string_view attr) {
    std::vector<double> v = parseList(e, attr, e.require(attr));
    if (v.size() != 3) e.fail("attribute '{}': expected 3 numbers, got {}", attr, v.size());
    return Vector3f(float(v[0]), float(v[1]), float(v[2]));
}

SpectrumValue tabulated(const Element& e, std::string_view text) {
    // Tolerate spaces around ':' ("400 : 0.5") by removing them before splitting.
    std::string compact;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (std::isspace(static_cast<unsigned char>(text[i]))) {
            std::size_t j = i;
            while (j < text.size() && std::isspace(static_cast<unsigned char>(text[j]))) ++j;
            bool nextColon = j < text.size() && text[j] == ':';
            bool prevColon = !compact.empty() && compact.back() == ':';
            if (nextColon || prevColon) { i = j - 1; continue; }
        }
        compact += text[i];
    }
    SpectrumValue s;
    for (std::string_view tok : tokens(e, "value", compact)) {
        std::size_t colon = tok.find(':');
        if (colon == tok.npos)
            e.fail("attribute 'value': expected 'wavelength:value' pairs, got '{}'", excerpt(tok));
        double l = checkedNumber(e, "wavelength", tok.substr(0, colon));
        double v = checkedNumber(e, "spectrum value", tok.substr(colon + 1));
        if (l <= 0) e.fail("wavelength {} nm is not positive", l);
        if (!s.lambdas.empty() && float(l) <= s.lambdas.back())
            e.fail("wavelengths must be strictly ascending: {} nm follows {} nm", l, s.lambdas.back());
        s.lambdas.push_back(float(l));
        s.values.push_back(float(v));
    }
    return s;
}

/// Two columns "λ value" per line; '#' starts a comment.
SpectrumValue spectrumFile(const Element& e, const std::filesystem::path& baseDir) {
    std::filesystem::path rel = e.require("filename");
    std::filesystem::path p = rel.is_absolute() ? rel : baseDir / rel;
    std::string text;
    try {
        text = readRegularFile(p, "spectrum file");  // refuses /dev/zero, FIFOs, folders
    } catch (const Error& err) {
        e.fail("{}", err.what());
    }
    SpectrumValue s;
    std::string_view rest = text;
    for (int n = 1; !rest.empty(); ++n) {
        std::size_t nl = rest.find('\n');
        std::string_view l = rest.substr(0, nl);
        rest.remove_prefix(nl == rest.npos ? rest.size() : nl + 1);
        l = trim(l.substr(0, l.find('#')));
        if (l.empty()) continue;
        std::size_t i = 0;
        std::vector<std::string_view> cols;
        while (i < l.size()) {
            std::size_t j = i;
            while (j < l.size() && !std::isspace(static_cast<unsigned char>(l[j]))) ++j;
            cols.push_back(l.substr(i, j - i));
            while (j < l.size() && std::isspace(static_cast<unsigned char>(l[j]))) ++j;
            i = j;
        }
        std::string where = fmt::format("{}:{}", p.string(), n);
        double lambda = 0, value = 0;
        if (cols.size() != 2 || !toDouble(cols[0], lambda) || !toDouble(cols[1], value) ||
            !std::isfinite(lambda) || !std::isfinite(value) || std::abs(value) > 3e38)
            e.fail("{}: expected two numbers 'wavelength value', got '{}'", where, excerpt(l));
        if (lambda <= 0) e.fail("{}: wavelength {} nm is not positive", where, lambda);
        if (!s.lambdas.empty() && float(lambda) <= s.lambdas.back())
            e.fail("{}: wavelengths must be strictly ascending: {} nm follows {} nm", where, lambda,
                   s.lambdas.back());
        s.lambdas.push_back(float(lambda));
        s.values.push_back(float(value));
    }
    if (s.lambdas.empty()) e.fail("spectrum file '{}' holds no data", excerpt(p.string(), 200));
    return s;
}

/// A named spectrum (value="d65", "macbeth-13"): one word that starts with a letter and
/// is not a number ("inf" and "nan" stay numbers, to be rejected as not finite).
bool isSpectrumName(std::string_view text) {
    std::string_view t = trim(text);
    double unused = 0;
    if (t.empty() || !std::isalpha(static_cast<unsigned char>(t.front())) || toDouble(t, unused)) return false;
    return std::all_of(t.begin(), t.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
    });
}

SpectrumValue blackbody(const Element& e) {
    std::string_view t = trim(e.require("temperature"));
    // Mitsuba 0.6 scenes write the unit: temperature="3200K".
    if (!t.empty() && (t.back() == 'K' || t.back() == 'k')) t.remove_suffix(1);
    SpectrumValue s;
    s.temperature = float(checkedNumber(e, "attribute 'temperature'", t));
    if (s.temperature <= 0.f) e.fail("attribute 'temperature': {} K is not positive", s.temperature);
    if (const std::string* sc = e.find("scale")) s.scale = float(checkedNumber(e, "attribute 'scale'", *sc));
    if (s.scale < 0.f) e.fail("attribute 'scale' must not be negative");
    return s;
}

} // namespace

std::string Element::describe() const {
    std::string s = name.empty() ? fmt::format("<{}>", excerpt(tag))
                                 : fmt::format("<{} name=\"{}\">", excerpt(tag), excerpt(name));
    return context.empty() ? s : s + " in " + context;
}

const std::string* Element::find(std::string_view attr) const {
    for (const auto& [k, v] : attrs)
        if (k == attr) return &v;
    return nullptr;
}

const std::string& Element::require(std::string_view attr) const {
    if (const std::string* v = find(attr)) return *v;
    fail("missing attribute '{}'", attr);
}

void Element::allowOnly(std::initializer_list<std::string_view> allowed) const {
    for (const auto& [k, v] : attrs) {
        bool ok = false;
        for (std::string_view a : allowed) ok = ok || a == k;
        if (ok) continue;
        std::vector<std::string> cands(allowed.begin(), allowed.end());
        std::string hint = didYouMean(k, cands);
        fail("unexpected attribute '{}'{}", excerpt(k), hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint));
    }
}

double parseNumber(const Element& e, std::string_view attr, std::string_view text) {
    return checkedNumber(e, fmt::format("attribute '{}'", attr), text);
}

std::int64_t parseInteger(const Element& e, std::string_view attr, std::string_view text) {
    std::string_view s = trim(text);
    if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
    std::int64_t v = 0;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec == std::errc::result_out_of_range) e.fail("attribute '{}': integer '{}' is out of range", attr, excerpt(s));
    if (s.empty() || ec != std::errc() || ptr != s.data() + s.size())
        e.fail("attribute '{}': cannot parse '{}' as an integer", attr, excerpt(trim(text)));
    return v;
}

bool parseBool(const Element& e, std::string_view attr, std::string_view text) {
    std::string s(trim(text));
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (s == "true") return true;
    if (s == "false") return false;
    e.fail("attribute '{}': expected 'true' or 'false', got '{}'", attr, excerpt(text));
}

std::vector<double> parseList(const Element& e, std::string_view attr, std::string_view text) {
    std::vector<double> out;
    for (std::string_view t : tokens(e, attr, text)) out.push_back(parseNumber(e, attr, t));
    return out;
}

Vector3f parseXYZ(const Element& e, float missing, bool allowScalar) {
    const std::string* value = e.find("value");
    bool any = e.find("x") || e.find("y") || e.find("z");
    if (value && any) e.fail("give either 'value' or 'x'/'y'/'z', not both");
    if (value) {
        std::vector<double> v = parseList(e, "value", *value);
        if (v.size() == 1 && allowScalar) return Vector3f(float(v[0]));
        if (v.size() != 3)
            e.fail("attribute 'value': expected {}3 numbers, got {}", allowScalar ? "1 or " : "", v.size());
        return Vector3f(float(v[0]), float(v[1]), float(v[2]));
    }
    if (!any) e.fail("missing attribute 'value' (or 'x'/'y'/'z')");
    Vector3f r(missing);
    const char* names[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i)
        if (const std::string* s = e.find(names[i])) r[i] = float(parseNumber(e, names[i], *s));
    return r;
}

PropertyValue parseProperty(const Element& e, const std::filesystem::path& baseDir) {
    const std::string& t = e.tag;
    if (t == "boolean" || t == "integer" || t == "float" || t == "string") {
        e.allowOnly({"name", "value"});
        const std::string& v = e.require("value");
        if (t == "boolean") return parseBool(e, "value", v);
        if (t == "integer") return parseInteger(e, "value", v);
        if (t == "float") return parseNumber(e, "value", v);
        return v;
    }
    if (t == "point" || t == "vector") {
        e.allowOnly({"name", "value", "x", "y", "z"});
        Vector3f v = parseXYZ(e, 0.f, false);
        return t == "point" ? PropertyValue(PointValue{v}) : PropertyValue(VectorValue{v});
    }
    if (t == "rgb") {
        e.allowOnly({"name", "value"});
        std::vector<double> v = parseList(e, "value", e.require("value"));
        if (v.size() == 1) return RGBValue{Vector3f(float(v[0]))};
        if (v.size() != 3) e.fail("attribute 'value': expected 1 or 3 numbers, got {}", v.size());
        return RGBValue{Vector3f(float(v[0]), float(v[1]), float(v[2]))};
    }
    if (t == "spectrum") {
        e.allowOnly({"name", "value", "filename"});
        const std::string* value = e.find("value");
        if (value && e.find("filename")) e.fail("give either 'value' or 'filename', not both");
        if (!value) return spectrumFile(e, baseDir);
        if (value->find(':') != std::string::npos) return tabulated(e, *value);
        if (isSpectrumName(*value)) {
            SpectrumValue s;
            s.name = std::string(trim(*value));  // resolved (and checked) by Properties::getSpectrum
            return s;
        }
        std::vector<double> v = parseList(e, "value", *value);
        if (v.size() != 1)
            e.fail("attribute 'value': expected one constant, 'wavelength:value' pairs or a spectrum name, got '{}'",
                   excerpt(*value));
        SpectrumValue s;
        s.values = {float(v[0])};
        return s;
    }
    if (t == "blackbody") {
        e.allowOnly({"name", "temperature", "scale"});
        return blackbody(e);
    }
    e.fail("not a property element");
}

void applyTransformOp(const Element& op, Transform& m) {
    const std::string& t = op.tag;
    if (t == "translate") {
        op.allowOnly({"value", "x", "y", "z"});
        m = Transform::translate(parseXYZ(op, 0.f, false)) * m;
    } else if (t == "rotate") {
        op.allowOnly({"value", "x", "y", "z", "angle"});
        Vector3f axis = parseXYZ(op, 0.f, false);
        float angle = float(parseNumber(op, "angle", op.require("angle")));
        if (axis == Vector3f(0.f)) op.fail("the rotation axis is zero");
        m = Transform::rotate(axis, angle) * m;
    } else if (t == "scale") {
        op.allowOnly({"value", "x", "y", "z"});
        Vector3f s = parseXYZ(op, 1.f, true);
        if (s.x == 0.f || s.y == 0.f || s.z == 0.f) op.fail("a zero scale factor makes the transform singular");
        m = Transform::scale(s) * m;
    } else if (t == "matrix") {
        op.allowOnly({"value"});
        std::vector<double> v = parseList(op, "value", op.require("value"));
        if (v.size() != 16 && v.size() != 9) op.fail("attribute 'value': expected 16 or 9 numbers, got {}", v.size());
        int n = v.size() == 16 ? 4 : 3;
        glm::mat4 a(1.f);
        // Written row-major; GLM indexes [column][row].
        for (int r = 0; r < n; ++r)
            for (int c = 0; c < n; ++c) a[c][r] = float(v[std::size_t(r * n + c)]);
        glm::mat4 inv = glm::inverse(a);
        bool finite = true;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(inv[c][r]);
        if (glm::determinant(a) == 0.f || !finite) op.fail("the matrix is singular");
        m = Transform(a, inv) * m;
    } else if (t == "lookat") {
        op.allowOnly({"origin", "target", "up"});
        Point3f origin = triple(op, "origin"), target = triple(op, "target");
        Vector3f up = op.find("up") ? triple(op, "up") : Vector3f(0.f, 1.f, 0.f);
        Vector3f dir = target - origin;
        if (dir == Vector3f(0.f)) op.fail("origin and target coincide");
        if (up == Vector3f(0.f)) op.fail("the up vector is zero");
        if (length(cross(normalize(dir), normalize(up))) < 1e-6f)
            op.fail("the up vector is parallel to the view direction");
        m = Transform::lookAt(origin, target, up) * m;
    } else {
        std::string hint = didYouMean(t, {"translate", "rotate", "scale", "matrix", "lookat"});
        op.fail("unknown transform operation{}", hint.empty() ? "" : fmt::format(" (did you mean <{}>?)", hint));
    }
}

} // namespace effigi::xml::detail

// What a RadiosityMesh stores and answers (effigi/render/radiosity_mesh.hpp): spectral
// reflectance and emission of the elements, vertex values, locating surface points, and
// the IIlluminationMap queries.
#include "effigi/render/radiosity_mesh.hpp"

#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace effigi {

namespace {

/// Barycentrics (b1, b2) of p in the triangle (q0, q1, q2), from the dual basis of its edges.
Point2f barycentrics(const Point3f& q0, const Point3f& q1, const Point3f& q2, const Point3f& p) {
    Vector3d e1(q1 - q0), e2(q2 - q0), d(p - q0);
    double a = glm::dot(e1, e1), b = glm::dot(e1, e2), c = glm::dot(e2, e2), det = a * c - b * b;
    if (!(det > 0.0)) return Point2f(1.f / 3.f);
    double s = (c * glm::dot(d, e1) - b * glm::dot(d, e2)) / det, t = (a * glm::dot(d, e2) - b * glm::dot(d, e1)) / det;
    return Point2f(float(s), float(t));
}

} // namespace

void RadiosityMesh::evaluateMaterials(std::span<const IShape* const> shapes) {
    const int nb = m_bins.count();
    constexpr int PerBin = 8;  // midpoint rule inside each bin
    const int m = nb * PerBin;  // a multiple of 4: the four hero slots cover it exactly
    const std::size_t n = m_elements.size();
    m_rho.assign(n * std::size_t(nb), 0.f);
    m_emission.assign(n * std::size_t(nb), 0.f);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        const MeshElement& e = m_elements[i];
        const IShape* shape = shapes[e.shape];
        auto pit = std::upper_bound(m_patches.begin(), m_patches.end(), std::uint32_t(i),
                                    [](std::uint32_t v, const Patch& p) { return v < p.firstElement; });
        const Patch& p = *(pit - 1);
        Vector3f d = e.centre - p.o;
        bool second = p.quad && dot(p.d1, d) + dot(p.d2, d) > 1.f;
        std::uint32_t tri = second ? p.tri[1] : p.tri[0];
        Point3f q0, q1, q2;
        shape->mesh()->triangle(tri, q0, q1, q2);
        Hit hit;
        hit.t = 1.f;
        hit.shape = e.shape;
        hit.prim = tri;
        hit.uv = barycentrics(q0, q1, q2, e.centre);
        Ray ray{e.centre + e.n, -e.n, Infinity};  // arrives along −n: wo = n, the front side
        SurfaceInteraction si = shape->interaction(ray, hit);
        const IBSDF* bsdf = shape->bsdf();
        const IEmitter* emitter = shape->emitter();
        bool reflects = bsdf && !bsdf->isPureSpecular();
        float* rho = &m_rho[i * nb];
        float* emit = &m_emission[i * nb];
        for (int k = 0; k < m / 4; ++k) {
            // sampleUniform(u) puts slot s at 360 + 470 u + 117.5 s nm: the midpoints
            // k + s·m/4 of an m-point grid, without wrapping for k < m/4.
            SampledWavelengths lambda = SampledWavelengths::sampleUniform((float(k) + 0.5f) / float(m));
            SampledSpectrum r = reflects ? bsdf->albedo(si, lambda) : SampledSpectrum(0.f);
            SampledSpectrum le = emitter ? emitter->eval(si, lambda) : SampledSpectrum(0.f);
            for (int s = 0; s < NSpectrumSamples; ++s) {
                int bin = (k + s * m / 4) / PerBin;
                rho[bin] += r[s];
                emit[bin] += le[s];
            }
        }
        for (int b = 0; b < nb; ++b) {
            float r = rho[b] / PerBin;
            rho[b] = std::isfinite(r) ? std::clamp(r, 0.f, 1.f) : 0.f;
            float l = emit[b] / PerBin * Pi;  // exitance of a Lambertian emitter: E = π L
            emit[b] = std::isfinite(l) ? std::max(l, 0.f) : 0.f;
        }
    });
}

void RadiosityMesh::radiosityChanged() {
    const int nb = m_bins.count();
    m_vertexRadiosity.assign(m_vertices.size() * std::size_t(nb), 0.f);
    tbb::parallel_for(std::size_t(0), m_vertices.size(), [&](std::size_t v) {
        float* out = &m_vertexRadiosity[v * nb];
        double area = 0.0;
        for (std::uint32_t i : vertexElements(std::uint32_t(v))) area += m_elements[i].area;
        if (!(area > 0.0)) return;
        for (std::uint32_t i : vertexElements(std::uint32_t(v))) {
            float w = float(m_elements[i].area / area);
            for (int b = 0; b < nb; ++b) out[b] += w * m_radiosity[std::size_t(i) * nb + b];
        }
    });
}

std::optional<MeshPoint> RadiosityMesh::locate(const SurfaceInteraction& si) const {
    auto it = m_shapeIndex.find(si.shape);
    if (it == m_shapeIndex.end()) return std::nullopt;
    std::uint64_t idx = m_triangleStart[it->second] + si.prim;
    if (idx >= m_triangleStart[it->second + 1] || m_trianglePatch[idx] == NoPatch) return std::nullopt;
    const Patch& p = m_patches[m_trianglePatch[idx]];
    Vector3f d = si.p - p.o;
    float s = std::max(dot(p.d1, d), 0.f), t = std::max(dot(p.d2, d), 0.f);
    MeshPoint mp;
    if (p.quad) {
        float x = std::min(s, 1.f) * float(p.nu), y = std::min(t, 1.f) * float(p.nv);
        std::uint32_t a = std::min(std::uint32_t(x), p.nu - 1), b = std::min(std::uint32_t(y), p.nv - 1);
        float fs = std::clamp(x - float(a), 0.f, 1.f), ft = std::clamp(y - float(b), 0.f, 1.f);
        mp.element = p.firstElement + b * p.nu + a;
        mp.weights = {(1.f - fs) * (1.f - ft), fs * (1.f - ft), fs * ft, (1.f - fs) * ft};
        return mp;
    }
    if (s + t > 1.f) {
        float scale = 1.f / (s + t);
        s *= scale;
        t *= scale;
    }
    std::uint32_t k = p.nu;
    float x = s * float(k), y = t * float(k);
    std::uint32_t j = std::min(std::uint32_t(y), k - 1);
    std::uint32_t i = std::min(std::uint32_t(x), k - 1 - j);
    float fx = std::max(x - float(i), 0.f), fy = std::max(y - float(j), 0.f);
    std::uint32_t rowStart = 2 * k * j - j * j;
    if (fx + fy <= 1.f || i + j + 1 >= k) {  // the "up" triangle (i,j), (i+1,j), (i,j+1)
        float w0 = std::max(1.f - fx - fy, 0.f), w1 = std::min(fx, 1.f), w2 = std::min(fy, 1.f), sum = w0 + w1 + w2;
        mp.element = p.firstElement + rowStart + 2 * i;
        mp.weights = {w0 / sum, w1 / sum, w2 / sum, 0.f};
    } else {  // the "down" triangle (i+1,j), (i+1,j+1), (i,j+1)
        float w0 = std::max(1.f - fy, 0.f), w1 = std::max(fx + fy - 1.f, 0.f), w2 = std::max(1.f - fx, 0.f);
        float sum = w0 + w1 + w2;
        mp.element = p.firstElement + rowStart + 2 * i + 1;
        mp.weights = {w0 / sum, w1 / sum, w2 / sum, 0.f};
    }
    return mp;
}

float RadiosityMesh::interpolated(const MeshPoint& p, int b) const {
    const MeshElement& e = m_elements[p.element];
    const int nb = m_bins.count();
    float v = 0.f;
    for (int k = 0; k < e.corners(); ++k) v += p.weights[k] * m_vertexRadiosity[std::size_t(e.vertices[k]) * nb + b];
    return v;
}

bool RadiosityMesh::covers(const SurfaceInteraction& si) const {
    return dot(si.n, si.wo) > 0.f && locate(si).has_value();
}

SampledSpectrum RadiosityMesh::radiance(const SurfaceInteraction& si, const SampledWavelengths& lambda) const {
    SampledSpectrum L(0.f);
    if (!(dot(si.n, si.wo) > 0.f)) return L;  // one-sided
    std::optional<MeshPoint> p = locate(si);
    if (!p) return L;
    for (int s = 0; s < NSpectrumSamples; ++s) {
        int b = m_bins.binOf(lambda[s]);
        if (b >= 0) L[s] = interpolated(*p, b) * InvPi;  // Lambertian: L = B / π
    }
    return L;
}

SampledSpectrum RadiosityMesh::irradiance(const SurfaceInteraction& si, const SampledWavelengths& lambda) const {
    SampledSpectrum H(0.f);
    if (!(dot(si.n, si.wo) > 0.f)) return H;
    std::optional<MeshPoint> p = locate(si);
    if (!p) return H;
    const int nb = m_bins.count();
    for (int s = 0; s < NSpectrumSamples; ++s) {
        int b = m_bins.binOf(lambda[s]);
        if (b < 0) continue;
        // B = E + ρ H: the irradiance is known where the element reflects.
        float rho = m_rho[std::size_t(p->element) * nb + b];
        if (rho > 0.f) H[s] = std::max(0.f, (interpolated(*p, b) - m_emission[std::size_t(p->element) * nb + b]) / rho);
    }
    return H;
}

} // namespace effigi

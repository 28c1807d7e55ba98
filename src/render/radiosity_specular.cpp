// Extended form factors through specular surfaces (effigi/render/radiosity_specular.hpp).
#include "effigi/render/radiosity_specular.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/imesh.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/radiosity_geometry.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>

namespace effigi {

SpecularTransfer::SpecularTransfer(Ref<IFormFactor> base, int rays, int maxDepth)
    : m_base(std::move(base)), m_rays(rays), m_maxDepth(maxDepth) {
    setIdentity("formfactor/specular+" + m_base->typeName(), "");
}

void SpecularTransfer::prepare(const FormFactorContext& context) {
    m_ctx = context;
    m_base->prepare(context);
    const IMesh& mesh = *m_ctx.mesh;
    const std::size_t n = mesh.elementCount();
    std::vector<std::map<std::uint32_t, double>> rows(n);
    if (!m_ctx.visibility) fail("specular transfer needs the scene's accelerator");
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        const MeshElement& e = mesh.elements()[i];
        PCG32 rng(mixBits(std::uint64_t(i) ^ mixBits(m_ctx.seed + 0x51ec)), 0x2545f491u);
        Frame frame(e.n);
        for (int r = 0; r < m_rays; ++r) {
            Point3f x = sampleElement(mesh, std::uint32_t(i), {rng.nextFloat(), rng.nextFloat()});
            Vector3f d = frame.toWorld(warp::squareToCosineHemisphere({rng.nextFloat(), rng.nextFloat()}));
            Ray ray{offsetRayOrigin(x, e.n, d), d, Infinity};
            SampledWavelengths lambda = SampledWavelengths::sampleUniform(rng.nextFloat());
            SampledSpectrum beta(1.f);
            for (int depth = 0; depth <= m_maxDepth; ++depth) {
                Hit hit;
                if (!m_ctx.visibility->intersect(ray, hit)) break;
                SurfaceInteraction si = m_ctx.shapes[hit.shape]->interaction(ray, hit);
                if (std::optional<MeshPoint> p = mesh.locate(si)) {
                    // Direct exchange is the base component's; after a specular bounce it is ours.
                    if (depth > 0 && dot(si.n, si.wo) > 0.f) {
                        SampledSpectrum pdf = lambda.pdf();
                        double sum = 0.0;
                        int live = 0;
                        for (int k = 0; k < NSpectrumSamples; ++k)
                            if (pdf[k] > 0.f) sum += beta[k], ++live;
                        double w = live ? sum / live : 0.0;
                        if (std::isfinite(w) && w > 0.0) rows[i][p->element] += w / m_rays;
                    }
                    break;
                }
                const IBSDF* bsdf = si.bsdf;
                if (!bsdf || !bsdf->hasSpecular() || depth == m_maxDepth) break;
                Vector3f wo = si.toLocal(si.wo);
                std::optional<BSDFSample> bs =
                    bsdf->sample(si, wo, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()}, lambda,
                                 TransportMode::Radiance);
                if (!bs || !bs->isSpecular() || !(bs->pdf > 0.f)) break;
                beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
                ray = si.spawnRay(si.toWorld(bs->wi));
            }
        }
    });
    // Compressed rows, then the transpose by counting.
    m_rowStart.assign(n + 1, 0);
    m_colStart.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        m_rowStart[i + 1] = m_rowStart[i] + rows[i].size();
        for (const auto& [j, v] : rows[i]) ++m_colStart[j + 1];
    }
    for (std::size_t j = 0; j < n; ++j) m_colStart[j + 1] += m_colStart[j];
    m_rowIndex.resize(m_rowStart[n]);
    m_rowValue.resize(m_rowStart[n]);
    m_colIndex.resize(m_rowStart[n]);
    m_colValue.resize(m_rowStart[n]);
    std::vector<std::size_t> fill(m_colStart.begin(), m_colStart.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t k = m_rowStart[i];
        for (const auto& [j, v] : rows[i]) {
            m_rowIndex[k] = j;
            m_rowValue[k++] = float(v);
            m_colIndex[fill[j]] = std::uint32_t(i);
            m_colValue[fill[j]++] = float(v);
        }
    }
}

double SpecularTransfer::formFactor(std::uint32_t i, std::uint32_t j) const {
    double f = m_base->formFactor(i, j);
    auto begin = m_rowIndex.begin() + std::ptrdiff_t(m_rowStart[i]), end = m_rowIndex.begin() + std::ptrdiff_t(m_rowStart[i + 1]);
    auto it = std::lower_bound(begin, end, j);
    if (it != end && *it == j) f += m_rowValue[std::size_t(it - m_rowIndex.begin())];
    return f;
}

void SpecularTransfer::row(std::uint32_t i, std::span<float> out) const {
    m_base->row(i, out);
    for (std::size_t k = m_rowStart[i]; k < m_rowStart[i + 1]; ++k) out[m_rowIndex[k]] += m_rowValue[k];
}

void SpecularTransfer::column(std::uint32_t i, std::span<float> out) const {
    m_base->column(i, out);
    for (std::size_t k = m_colStart[i]; k < m_colStart[i + 1]; ++k) out[m_colIndex[k]] += m_colValue[k];
}

} // namespace effigi

// subdiv — a subdivision surface refined by OpenSubdiv from a polygonal control cage and
// handed on as a triangle mesh (so every accelerator traces it).
//
// Parameters: filename (an .obj or .ply cage) or the inline cage positions ("x y z, ...")
// and faces ("i j k ..., ...", vertex indices from 0); scheme (catmark: Catmull–Clark,
// any polygons; loop: triangles only); level (uniform refinement steps); crease ("v0 v1
// sharpness, ...": edge sharpness, added to the OBJ file's `t crease` tags; 10 or more is
// infinitely sharp, s < 10 a semi-sharp crease that softens after s steps); boundary
// (edge_and_corner: boundary edges and corners of valence 2 interpolated, the default of
// RenderMan and OpenSubdiv's examples; edge_only: boundary edges only, corners rounded;
// when boundary is not given, an OBJ cage's `t interpolateboundary` tag chooses: 1 edge
// and corner, else edge only, since its 0 (none) differs only in patch evaluation);
// flip_tex_coords (default true for OBJ, false for PLY, as the obj and ply shapes);
// to_world, flip_normals, face_normals, bsdf, emitter.
//
// Every vertex of the refined level is projected onto the limit surface with its limit
// tangents (OpenSubdiv's PrimvarRefiner::Limit), whose cross product is the vertex
// normal; so the mesh is inscribed in the true limit surface and shading is smooth. Along
// infinitely sharp creases the limit surface has no single normal: those vertices are
// split into the sectors between the creases, each with the area-weighted normal of its
// own refined faces, so creases stay sharp in shading too. uv (when the cage has them) are
// face-varying, refined and projected to the limit likewise, linear at face-varying
// corners only (RenderMan's default), so seams keep their uv while the interior is smooth.
// Uniform refinement only: a triangle mesh needs every face refined to the same level
// (feature-adaptive refinement feeds patch evaluation, which this shape does not do).
// OpenSubdiv is linked into this module alone; it loads only for a scene that uses subdiv.
// References: E. Catmull, J. Clark, "Recursively generated B-spline surfaces on arbitrary
// topological meshes", CAD 1978; C. Loop, "Smooth subdivision surfaces based on
// triangles", MSc thesis, 1987; T. DeRose, M. Kass, T. Truong, "Subdivision surfaces in
// character animation", SIGGRAPH 1998 (creases); Pixar, OpenSubdiv 3 documentation.
#include "subdiv_cage.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/render/shape_base.hpp"

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <memory>
#include <numeric>
#include <set>

namespace effigi {
namespace {

namespace osd = OpenSubdiv::Far;
using OpenSubdiv::Sdc::Options;

/// A primvar for OpenSubdiv's templated refiner: a point in double precision.
template <class V> struct Primvar {
    V v{0.0};
    void Clear(void* = nullptr) { v = V(0.0); }
    void AddWithWeight(const Primvar& s, double w) { v += w * s.v; }
};
using Point = Primvar<Vector3d>;
using Uv = Primvar<glm::dvec2>;

thread_local std::string osdError;  // OpenSubdiv reports through a global C callback

/// Checks what OpenSubdiv would otherwise reject or index out of range.
void validateCage(const Properties& p, const subdiv::Cage& c, bool loop, const std::string& what) {
    const int nv = int(c.positions.size());
    std::set<std::pair<int, int>> edges;
    for (std::size_t f = 0, at = 0; f < c.faceSizes.size(); at += std::size_t(c.faceSizes[f++])) {
        const int n = c.faceSizes[f];
        if (n < 3) fail("{}: face {} has {} vertices (at least 3)", what, f + 1, n);
        if (loop && n != 3)
            failAt(p.whereOf("scheme"), "{}: scheme=loop needs a triangle cage: face {} has {} vertices", what, f + 1, n);
        for (int k = 0; k < n; ++k) {
            int a = c.faceVerts[at + std::size_t(k)], b = c.faceVerts[at + std::size_t((k + 1) % n)];
            if (a < 0 || a >= nv) fail("{}: face {} uses vertex {}, out of range (cage has {})", what, f + 1, a, nv);
            if (!c.uvIndices.empty() && std::size_t(c.uvIndices[at + std::size_t(k)]) >= c.uvs.size())
                fail("{}: face {} uses texture coordinate {}, out of range", what, f + 1, c.uvIndices[at + std::size_t(k)]);
            edges.insert(std::minmax(a, b));
        }
    }
    if (c.faceSizes.empty()) fail("{}: the cage has no faces", what);
    for (std::size_t k = 0; k < c.creaseWeights.size(); ++k)
        if (!edges.count(std::minmax(c.creasePairs[2 * k], c.creasePairs[2 * k + 1])) || !(c.creaseWeights[k] >= 0.f))
            fail("{}: crease {} ({} {} {}) is not an edge of the cage with a sharpness >= 0", what, k + 1,
                 c.creasePairs[2 * k], c.creasePairs[2 * k + 1], c.creaseWeights[k]);
    for (std::size_t k = 0; k < c.corners.size(); ++k)
        if (c.corners[k] < 0 || c.corners[k] >= nv || !(c.cornerWeights[k] >= 0.f))
            fail("{}: corner {} (vertex {}) is out of range or has a negative sharpness", what, k + 1, c.corners[k]);
}

class Subdiv final : public MeshShape {
public:
    static Schema schema() {
        Schema s("shape", "subdiv", "Subdivision surface (OpenSubdiv: Catmull–Clark or Loop, creases) from a control cage.");
        s.cite("Catmull & Clark 1978; Loop 1987; DeRose, Kass & Truong, SIGGRAPH 1998; Pixar, OpenSubdiv 3");
        s.optional("filename", ParamType::String, "Control cage: an .obj or .ply file, relative to the scene file");
        s.optional("positions", ParamType::String, "Inline cage vertices \"x y z, ...\" (without filename)");
        s.optional("faces", ParamType::String, "Inline cage faces \"i j k ..., ...\", vertex indices from 0");
        s.string("scheme", "catmark", "catmark (Catmull–Clark) or loop (triangle cages)").oneOf({"catmark", "loop"});
        s.integer("level", 3, "Uniform refinement level").range(0, 10);
        s.optional("crease", ParamType::String, "Edge creases \"v0 v1 sharpness, ...\" (10: infinitely sharp)");
        s.string("boundary", "edge_and_corner", "Boundary interpolation: edge_and_corner (corners of valence 2 kept) or edge_only")
            .oneOf({"edge_and_corner", "edge_only"});
        s.optional("flip_tex_coords", ParamType::Bool, "Flip v (v -> 1 - v); default true for OBJ, false for PLY");
        addMeshParams(s);
        // effigi-conform: a cube cage, the same with its top edges creased (inline), and
        // a Loop tetrahedron from a PLY file, tiny and flipped.
        const std::string cube = "-1 -1 -1, 1 -1 -1, 1 1 -1, -1 1 -1, -1 -1 1, 1 -1 1, 1 1 1, -1 1 1",
                          faces = "0 3 2 1, 4 5 6 7, 0 1 5 4, 1 2 6 5, 2 3 7 6, 3 0 4 7";
        s.addConformance({"cube", {{"positions", cube}, {"faces", faces}}});
        s.addConformance({"creased cube", {{"positions", cube}, {"faces", faces}, {"level", std::int64_t(2)},
                                           {"crease", std::string("4 5 10, 5 6 10, 6 7 10, 7 4 10")}}});
        s.addConformance({"loop tetrahedron tiny flipped", {{"filename", std::string("tests/data/shapes/tetrahedron.ply")},
                                                            {"scheme", std::string("loop")}, {"flip_normals", true},
                                                            {"to_world", Transform::scale(Vector3f(1e-3f))}}});
        return s;
    }

    explicit Subdiv(const Properties& p) : MeshShape(p) {
        subdiv::Cage cage;
        std::string what = p.describe();
        const bool loop = p.getString("scheme") == "loop";
        if (p.has("filename")) {
            if (p.has("positions") || p.has("faces"))
                failAt(p.whereOf("positions"), "{}: give filename or positions and faces, not both", what);
            std::string file = p.getPath("filename").string(), ext = p.getPath("filename").extension().string();
            std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
            bool flip = p.has("flip_tex_coords") ? p.getBool("flip_tex_coords") : ext == ".obj";
            try {
                if (ext != ".obj" && ext != ".ply") fail("{}: the cage must be an .obj or .ply file", file);
                cage = ext == ".obj" ? subdiv::readObjCage(file, flip) : subdiv::readPlyCage(file, flip);
            } catch (const Error& e) {  // the file's own problem, prefixed with where the scene names it
                failAt(p.whereOf("filename"), "{}: {}", what, e.what());
            }
            what = file;
        } else {
            if (!p.has("positions") || !p.has("faces")) failAt(p.where(), "{}: needs filename, or positions and faces", what);
            cage = subdiv::inlineCage(p);
        }
        if (p.has("crease"))
            for (const std::vector<double>& t : procedural::parseTuples(p, "crease", 3, 1)) {
                if (t[0] != std::floor(t[0]) || t[1] != std::floor(t[1]) || std::abs(t[0]) + std::abs(t[1]) > 2e9)
                    failAt(p.whereOf("crease"), "{}: parameter 'crease': '{} {}' are not vertex indices", what, t[0], t[1]);
                cage.creasePairs.insert(cage.creasePairs.end(), {int(t[0]), int(t[1])});
                cage.creaseWeights.push_back(float(t[2]));
            }
        try {
            validateCage(p, cage, loop, p.has("filename") ? what : "the cage");
        } catch (const Error& e) {
            if (e.where().known()) throw;
            failAt(p.whereOf(p.has("filename") ? "filename" : "faces"), "{}: {}", p.describe(), e.what());
        }
        setMesh(refine(p, cage, loop), what);
    }

private:
    static TriangleMesh refine(const Properties& p, const subdiv::Cage& c, bool loop) {
        const int level = int(p.getInt("level"));
        // Triangles at the last level: an n-gon gives n quads (Catmull–Clark) at the first
        // step, each quad or triangle gives four at every step.
        double tris = (loop ? double(c.faceSizes.size()) : 0.5 * std::accumulate(c.faceSizes.begin(), c.faceSizes.end(), 0.0)) *
                      std::pow(4.0, level);
        if (tris > 1e7)
            failAt(p.whereOf("level"), "{}: level {} would make about {:.3g} triangles (at most 1e7)", p.describe(), level, tris);

        osd::TopologyDescriptor d;
        d.numVertices = int(c.positions.size());
        d.numFaces = int(c.faceSizes.size());
        d.numVertsPerFace = c.faceSizes.data();
        d.vertIndicesPerFace = c.faceVerts.data();
        d.numCreases = int(c.creaseWeights.size());
        d.creaseVertexIndexPairs = c.creasePairs.data();
        d.creaseWeights = c.creaseWeights.data();
        d.numCorners = int(c.corners.size());
        d.cornerVertexIndices = c.corners.data();
        d.cornerWeights = c.cornerWeights.data();
        osd::TopologyDescriptor::FVarChannel uvChannel;
        const bool uvs = !c.uvs.empty();
        if (uvs) {
            uvChannel.numValues = int(c.uvs.size());
            uvChannel.valueIndices = c.uvIndices.data();
            d.numFVarChannels = 1;
            d.fvarChannels = &uvChannel;
        }
        Options o;
        const int tag = p.find("boundary")->fromDefault ? c.interpolateBoundary : -1;
        const bool edgeOnly = tag >= 0 ? tag != 1 : p.getString("boundary") == "edge_only";
        o.SetVtxBoundaryInterpolation(edgeOnly ? Options::VTX_BOUNDARY_EDGE_ONLY : Options::VTX_BOUNDARY_EDGE_AND_CORNER);
        o.SetFVarLinearInterpolation(Options::FVAR_LINEAR_CORNERS_ONLY);
        using Factory = osd::TopologyRefinerFactory<osd::TopologyDescriptor>;
        osdError.clear();
        osd::SetErrorCallback([](osd::ErrorType, const char* m) { if (osdError.empty()) osdError = m; });
        osd::SetWarningCallback([](const char* m) { log::debug("OpenSubdiv: {}", m); });
        std::unique_ptr<osd::TopologyRefiner> r(
            Factory::Create(d, Factory::Options(loop ? OpenSubdiv::Sdc::SCHEME_LOOP : OpenSubdiv::Sdc::SCHEME_CATMARK, o)));
        if (!r) failAt(p.where(), "{}: OpenSubdiv rejects the cage: {}", p.describe(), excerpt(osdError, 200));
        osd::TopologyRefiner::UniformOptions uo(level);
        uo.fullTopologyInLastLevel = true;
        r->RefineUniform(uo);

        // Refine level by level, then project the last level onto the limit surface.
        const osd::PrimvarRefinerReal<double> primvar(*r);
        std::vector<Point> pos(std::size_t(r->GetNumVerticesTotal()));
        std::vector<Uv> uv(uvs ? std::size_t(r->GetNumFVarValuesTotal(0)) : 0);
        for (std::size_t i = 0; i < c.positions.size(); ++i) pos[i].v = c.positions[i];
        for (std::size_t i = 0; i < c.uvs.size(); ++i) uv[i].v = glm::dvec2(c.uvs[i]);
        Point* src = pos.data();
        Uv* srcUv = uv.data();
        for (int l = 1; l <= level; ++l) {
            Point* dst = src + r->GetLevel(l - 1).GetNumVertices();
            primvar.Interpolate(l, src, dst);
            src = dst;
            if (uvs) {
                Uv* dstUv = srcUv + r->GetLevel(l - 1).GetNumFVarValues(0);
                primvar.InterpolateFaceVarying(l, srcUv, dstUv, 0);
                srcUv = dstUv;
            }
        }
        const osd::TopologyLevel& top = r->GetLevel(level);
        const auto nv = std::size_t(top.GetNumVertices());
        std::vector<Point> lim(nv), du(nv), dv(nv);
        primvar.Limit(src, lim, du, dv);
        std::vector<Uv> limUv(uvs ? std::size_t(top.GetNumFVarValues(0)) : 0);
        if (uvs) primvar.LimitFaceVarying(srcUv, limUv, 0);
        return triangulate(top, lim, du, dv, limUv);
    }

    /// The refined faces as triangles; a vertex is repeated per uv value and, on an
    /// infinitely sharp crease, per sector between the creases.
    static TriangleMesh triangulate(const osd::TopologyLevel& top, const std::vector<Point>& lim, const std::vector<Point>& du,
                                    const std::vector<Point>& dv, const std::vector<Uv>& limUv) {
        const bool uvs = !limUv.empty();
        auto faceNormal = [&](int f) {  // area-weighted (Newell's method on the limit points)
            Vector3d n(0.0);
            auto fv = top.GetFaceVertices(f);
            for (int k = 0; k < fv.size(); ++k)
                n += glm::cross(lim[std::size_t(fv[k])].v, lim[std::size_t(fv[(k + 1) % fv.size()])].v);
            return n;
        };
        // The sector of face f around vertex v: the least face reachable from f across
        // edges at v that are not infinitely sharp (-1: v is on no such crease).
        auto sector = [&](int v, int f) {
            auto ve = top.GetVertexEdges(v);
            bool creased = false;
            for (int e : ve) creased = creased || top.IsEdgeInfSharp(e);
            if (!creased) return -1;
            std::vector<int> reached{f};
            for (std::size_t k = 0; k < reached.size(); ++k)
                for (int e : ve)
                    if (!top.IsEdgeInfSharp(e)) {
                        auto ef = top.GetEdgeFaces(e);
                        if (std::find(ef.begin(), ef.end(), reached[k]) == ef.end()) continue;
                        for (int g : ef)
                            if (std::find(reached.begin(), reached.end(), g) == reached.end()) reached.push_back(g);
                    }
            return *std::min_element(reached.begin(), reached.end());
        };
        TriangleMesh m;
        struct Split { int uv, sector; std::uint32_t out; };
        std::vector<std::vector<Split>> splits(lim.size());
        std::vector<Vector3d> sectorNormal;  // accumulated, per output vertex (zero: use the limit normal)
        std::vector<std::uint32_t> poly;
        for (int f = 0; f < top.GetNumFaces(); ++f) {
            auto fv = top.GetFaceVertices(f);
            poly.clear();
            for (int k = 0; k < fv.size(); ++k) {
                const int v = fv[k], u = uvs ? top.GetFaceFVarValues(f, 0)[k] : -1, s = sector(v, f);
                auto& list = splits[std::size_t(v)];
                auto it = std::find_if(list.begin(), list.end(), [&](const Split& x) { return x.uv == u && x.sector == s; });
                if (it == list.end()) {
                    Vector3d n = glm::cross(du[std::size_t(v)].v, dv[std::size_t(v)].v);
                    list.push_back({u, s, std::uint32_t(m.positions.size())});
                    it = list.end() - 1;
                    m.positions.emplace_back(lim[std::size_t(v)].v);
                    m.normals.emplace_back(glm::length(n) > 0.0 ? glm::normalize(n) : n);
                    if (uvs) m.uvs.emplace_back(limUv[std::size_t(u)].v);
                    sectorNormal.emplace_back(0.0);
                }
                if (s >= 0 || !(glm::length(m.normals[it->out]) > 0.f)) sectorNormal[it->out] += faceNormal(f);
                poly.push_back(it->out);
            }
            for (std::size_t k = 1; k + 1 < poly.size(); ++k) m.indices.insert(m.indices.end(), {poly[0], poly[k], poly[k + 1]});
        }
        for (std::size_t i = 0; i < sectorNormal.size(); ++i)
            if (glm::length(sectorNormal[i]) > 0.0) m.normals[i] = Normal3f(glm::normalize(sectorNormal[i]));
        return m;
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Subdiv)

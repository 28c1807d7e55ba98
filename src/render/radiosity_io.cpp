// Saving and loading a radiosity solution (effigi/render/radiosity_mesh.hpp), so that
// views of a walk-through reuse one solve.
//
// Format: one text line "effigi-radiosity 1 <elements> <bins> <fingerprint>\n", then
// elements × bins little-endian float32 radiosities, element-major. The fingerprint is a
// 64-bit FNV-1a hash of every element's centre, normal and area: a file only loads into
// a mesh built from the same scene with the same mesh parameters.
#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"
#include "effigi/render/radiosity_mesh.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <vector>
#include <sstream>

namespace effigi {

namespace {

constexpr const char* Magic = "effigi-radiosity";

std::uint64_t fingerprint(const IMesh& mesh) {
    std::uint64_t h = 1469598103934665603ull;
    auto add = [&](float v) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, 4);
        for (int k = 0; k < 4; ++k) {
            h ^= (bits >> (8 * k)) & 0xffu;
            h *= 1099511628211ull;
        }
    };
    for (const MeshElement& e : mesh.elements()) {
        for (int k = 0; k < 3; ++k) add(e.centre[k]);
        for (int k = 0; k < 3; ++k) add(e.n[k]);
        add(e.area);
    }
    return h;
}

} // namespace

void saveRadiositySolution(const IMesh& mesh, const std::filesystem::path& file) {
    std::ofstream out(file, std::ios::binary);
    if (!out) fail("cannot write radiosity solution {}: cannot open the file", file.string());
    out << Magic << " 1 " << mesh.elementCount() << ' ' << mesh.bins().count() << ' ' << fingerprint(mesh) << '\n';
    std::span<const float> b = mesh.radiosity();
    static_assert(std::endian::native == std::endian::little, "the solution file is little-endian");
    out.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size() * sizeof(float)));
    if (!out) fail("cannot write radiosity solution {}: write failed", file.string());
}

void loadRadiositySolution(IMesh& mesh, const std::filesystem::path& file) {
    regularFileSize(file, "radiosity solution");  // a device or FIFO would never end or block
    std::ifstream in(file, std::ios::binary);
    if (!in) fail("cannot read radiosity solution {}: no such file", file.string());
    std::string header;
    std::getline(in, header);
    std::istringstream hs(header);
    std::string magic;
    int version = 0, bins = 0;
    std::uint64_t elements = 0, print = 0;
    hs >> magic >> version >> elements >> bins >> print;
    if (!hs || magic != Magic || version != 1)
        fail("cannot read radiosity solution {}: not an effigi radiosity solution (bad header)", file.string());
    if (elements != mesh.elementCount() || bins != mesh.bins().count() || print != fingerprint(mesh))
        fail("radiosity solution {} was computed for another mesh ({} elements, {} bins; this mesh has {} and {}, "
             "or the geometry differs): solve again",
             file.string(), elements, bins, mesh.elementCount(), mesh.bins().count());
    std::span<float> b = mesh.radiosity();
    std::vector<float> values(b.size());  // checked before the mesh is touched
    in.read(reinterpret_cast<char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
    if (!in || in.gcount() != std::streamsize(values.size() * sizeof(float)))
        fail("cannot read radiosity solution {}: the file is truncated", file.string());
    for (float v : values)
        if (!std::isfinite(v) || v < 0.f)
            fail("cannot read radiosity solution {}: it holds a negative or non-finite value", file.string());
    std::copy(values.begin(), values.end(), b.begin());
    mesh.radiosityChanged();
}

} // namespace effigi

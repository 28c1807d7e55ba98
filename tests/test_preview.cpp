// effigi render --preview (apps/effigi/preview_server.cpp): while a render runs, the
// server answers the page, /status.json (progress, samples/s, the relMSE estimate and its
// history, which falls as samples accumulate) and /image.png (the image so far, exposure
// applied); headless Chromium loaded with the page shows that image where the layout puts
// it; a render nobody watches writes the very image of a render without --preview; a
// taken port and a bad one are one-line errors. Renders run in the background and are
// stopped with SIGINT; each case takes a few seconds.
#include "app_runner.hpp"
#include "image_helpers.hpp"
#include "preview_helpers.hpp"
#include "skip.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <set>

namespace fs = std::filesystem;
using namespace effigi::test;

namespace {

const std::string Scene = EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml";

/// False (after saying why) in a build without the preview (no cpp-httplib).
bool previewBuilt() {
    const AppResult r = runApp("render " + Scene + " --preview 0 --dry-run");
    if (r.out.find("built without the live preview") == std::string::npos) return true;
    skipTest("this effigi was built without the live preview (cpp-httplib was absent at configure time)");
    return false;
}

/// A 64 x 64 Cornell box rendering for up to 30 s with the preview on a free port.
std::vector<std::string> longRender(const fs::path& dir) {
    return {"render", Scene, "-D", "res=64", "--time", "30", "--preview", "0", "--no-progress", "-o",
            (dir / "out.exr").string()};
}

/// The status once the render has published at least `points` relMSE estimates.
std::string statusWithHistory(int port, std::size_t points) {
    std::string json;
    for (int i = 0; i < 300; ++i) {
        json = httpGet(port, "/status.json").body;
        if (jsonHistory(json).size() >= points) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return json;
}

/// Mean of each of the first three channels over [x0, x1) x [y0, y1), and the standard
/// deviation of their sum over the same pixels.
struct RegionStats {
    std::array<double, 3> mean{};
    double spread = 0.0;
    std::size_t colours = 0;
};
RegionStats regionStats(const ExrImage& img, int x0, int y0, int x1, int y1) {
    RegionStats s;
    double sum = 0.0, sum2 = 0.0, n = 0.0;
    std::set<std::array<int, 3>> colours;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            double v = 0.0;
            std::array<int, 3> c{};
            for (int k = 0; k < 3; ++k) {
                s.mean[std::size_t(k)] += img.at(x, y, k), v += img.at(x, y, k);
                c[std::size_t(k)] = int(std::lround(img.at(x, y, k) * 255.f));
            }
            sum += v, sum2 += v * v, n += 1.0, colours.insert(c);
        }
    for (double& m : s.mean) m /= n;
    s.spread = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
    s.colours = colours.size();
    return s;
}

ExrImage decodePng(const std::string& bytes, const fs::path& file) {
    std::ofstream(file, std::ios::binary) << bytes;
    return readExr(file);
}

} // namespace

TEST_CASE("preview serves the status and the image while the render runs", "[preview]") {
    if (!previewBuilt()) return;
    const fs::path dir = tempDir("preview-serve");
    BackgroundApp app(longRender(dir), dir / "log.txt");
    const int port = app.port();
    INFO(app.output());
    REQUIRE(port > 0);

    const std::string json = statusWithHistory(port, 4);
    INFO(json);
    CHECK(json.find("\"renderer\":\"renderer/path\"") != std::string::npos);
    CHECK(jsonNumber(json, "frame") >= 1);
    CHECK(jsonNumber(json, "width") == 64);
    CHECK(jsonNumber(json, "samplesPerSecond") > 0);
    const double progress = jsonNumber(json, "progress");
    CHECK((progress > 0 && progress < 1));
    CHECK(jsonNumber(json, "relmse") > 0);
    // One pass at least doubles the samples, so the estimate of relMSE (∝ 1/spp) falls by
    // about half from point to point: after three more it is far below the first.
    const auto history = jsonHistory(json);
    REQUIRE(history.size() >= 4);
    for (std::size_t i = 1; i < history.size(); ++i) CHECK(history[i].first > history[i - 1].first);
    CHECK(history.back().second < 0.5 * history.front().second);

    const HttpReply png = httpGet(port, "/image.png");
    REQUIRE(png.status == 200);
    CHECK(png.contentType == "image/png");
    const ExrImage img = decodePng(png.body, dir / "image.png");
    REQUIRE(img.spec.width == 64);
    REQUIRE(img.spec.height == 64);
    const RegionStats plain = regionStats(img, 0, 0, 64, 64);
    CHECK(plain.spread > 0.1);  // red and green walls, a white ceiling, dark corners: no constant picture
    const RegionStats bright = regionStats(decodePng(httpGet(port, "/image.png?exposure=2").body, dir / "b.png"),
                                           0, 0, 64, 64);
    for (int c = 0; c < 3; ++c) CHECK(bright.mean[std::size_t(c)] > 1.3 * plain.mean[std::size_t(c)]);

    const HttpReply page = httpGet(port, "/");
    CHECK(page.status == 200);
    CHECK(page.body.find("<img id=\"img\"") != std::string::npos);
    // Self-contained: nothing is fetched from another host (no CDN).
    CHECK(page.body.find("http://") == std::string::npos);
    CHECK(page.body.find("https://") == std::string::npos);
    CHECK(httpGet(port, "/no-such-thing").status == 404);

    CHECK(app.interrupt() == 130);  // stopped: the partial image is written
    CHECK(fs::exists(dir / "out.exr"));
    fs::remove_all(dir);
}

TEST_CASE("preview page in headless Chromium shows the image", "[preview]") {
    if (!previewBuilt()) return;
    std::string chromium;
    for (const char* name : {"chromium", "chromium-browser"})
        if (chromium.empty() && std::system(("command -v " + std::string(name) + " >/dev/null 2>&1").c_str()) == 0)
            chromium = name;
    if (chromium.empty())
        return skipTest("Chromium is absent (Debian package chromium, scripts/install-deps.sh): the preview page "
                        "was not loaded in a browser");
    const fs::path dir = tempDir("preview-chromium");
    BackgroundApp app(longRender(dir), dir / "log.txt");
    const int port = app.port();
    INFO(app.output());
    REQUIRE(port > 0);
    statusWithHistory(port, 2);  // an image to show as soon as the page asks
    const RegionStats served = regionStats(decodePng(httpGet(port, "/image.png").body, dir / "image.png"), 0, 0,
                                           64, 64);

    const fs::path shot = dir / "shot.png";
    const std::string cmd = fmt::format(
        "timeout 90 {} --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run "
        "--user-data-dir={} --window-size=800,600 --virtual-time-budget=3000 --screenshot={} "
        "http://127.0.0.1:{}/ > {} 2>&1",
        chromium, (dir / "profile").string(), shot.string(), port, (dir / "chromium.log").string());
    const int rc = std::system(cmd.c_str());
    INFO(cmd);
    REQUIRE(rc == 0);
    REQUIRE(fs::exists(shot));
    const ExrImage page = readExr(shot);
    REQUIRE(page.spec.width == 800);
    REQUIRE(page.spec.height == 600);
    // The image box is 512 x 512 at (16, 64) in an 800 x 600 window (preview_page.hpp).
    // There the page must show the render: varied pixels (an empty box is one colour, a
    // broken-image icon a few) whose mean colour is the served image's (the pixelated
    // upscaling keeps means; a later frame of the same render differs little).
    const RegionStats shown = regionStats(page, 16 + 4, 64 + 4, 16 + 512 - 4, 64 + 512 - 4);
    INFO("shown mean " << shown.mean[0] << " " << shown.mean[1] << " " << shown.mean[2] << ", served mean "
                       << served.mean[0] << " " << served.mean[1] << " " << served.mean[2]);
    CHECK(shown.colours > 200);
    CHECK(shown.spread > 0.1);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(shown.mean[std::size_t(c)] - served.mean[std::size_t(c)]) < 0.06);

    CHECK(app.interrupt() == 130);
    fs::remove_all(dir);
}

TEST_CASE("preview with nobody watching leaves the image unchanged", "[preview]") {
    if (!previewBuilt()) return;
    const fs::path dir = tempDir("preview-same");
    const std::string common = "render " + Scene + " -D res=32 --seed 7 --no-progress -o " + dir.string();
    // Without a page the passes are the render's own, so the samples and their sums are
    // too: equal floats. 1024 spp take about 3 s here: the last pass (512 spp) is longer
    // than the second a watched render's passes are cut to, so cutting it would show.
    const AppResult plain = runApp(common + "/a.exr --spp 1024");
    const AppResult previewed = runApp(common + "/b.exr --spp 1024 --preview 0");
    // Without --spp, --preview renders the sampler's count in passes, as --spp does.
    const AppResult bySpp = runApp(common + "/c.exr -D spp=8 --spp 8");
    const AppResult bySampler = runApp(common + "/d.exr -D spp=8 --preview 0");
    INFO(plain.out << previewed.out << bySpp.out << bySampler.out);
    for (const AppResult* r : {&plain, &previewed, &bySpp, &bySampler}) REQUIRE(r->exitCode == 0);
    CHECK(previewed.out.find("preview: http://127.0.0.1:") != std::string::npos);
    const ExrImage a = readExr(dir / "a.exr"), b = readExr(dir / "b.exr");
    REQUIRE(a.px.size() == 32 * 32 * 3);
    CHECK(a.px == b.px);
    CHECK(readExr(dir / "c.exr").px == readExr(dir / "d.exr").px);
    fs::remove_all(dir);
}

TEST_CASE("preview on a taken or invalid port is a one-line error", "[preview]") {
    if (!previewBuilt()) return;
    // A port held by a listening socket of this process.
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
    REQUIRE(listen(fd, 1) == 0);
    socklen_t len = sizeof addr;
    getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
    const int port = ntohs(addr.sin_port);
    const AppResult taken = runApp("render " + Scene + " -D res=8 -D spp=1 --preview " + std::to_string(port) +
                                   " -o " + (fs::temp_directory_path() / "effigi-preview-taken.exr").string());
    close(fd);
    INFO(taken.out);
    CHECK(taken.exitCode == 1);
    CHECK(taken.out.find("--preview: cannot listen on 127.0.0.1:" + std::to_string(port)) != std::string::npos);
    CHECK(std::count(taken.out.begin(), taken.out.end(), '\n') == 1);

    const AppResult bad = runApp("render " + Scene + " --preview 70000 --dry-run");
    INFO(bad.out);
    CHECK(bad.exitCode == 1);
    CHECK(bad.out.find("--preview expects a port in 0..65535, got '70000'") != std::string::npos);
}

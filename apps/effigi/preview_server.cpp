// The live preview's server (effigi render --preview; preview_server.hpp says what it
// shows), built as the module lib/effigi/preview.so (apps/CMakeLists.txt) that the app
// dlopens for --preview only (preview_load.cpp). cpp-httplib (https://github.com/yhirose/cpp-httplib; Debian libcpp-httplib-dev)
// serves three things on 127.0.0.1: the page (preview_page.hpp: one self-contained HTML
// file, no script, style or font from elsewhere, so it works offline), /status.json (the
// numbers, polled by the page every second) and /image.png?exposure=E&tonemap=T (the
// latest copy of the image, exposed and tone mapped as hdrfilm's PNG is).
//
// The render thread hands over a copy of the developed film after each pass (publish());
// the server's threads only ever read those copies, under a mutex, and encode the PNG
// themselves, once per image, exposure and tone map.
#include "preview_server.hpp"

#include "preview_page.hpp"

#include "effigi/core/log.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/image_metrics.hpp"
#include "effigi/render/tonemap.hpp"
#include "effigi/spectral/colorspace.hpp"

#include "hdrfilm_png.hpp"  // components/film: the display encoding and PNG writer of hdrfilm

#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <thread>
#include <type_traits>

namespace effigi::app {

namespace {

using Clock = std::chrono::steady_clock;

/// A page counts as watching while its last request is this recent (it polls every second).
constexpr auto WatchWindow = std::chrono::seconds(3);
/// The pass length while a page watches: the page's refresh interval.
constexpr double WatchedPassSeconds = 1.0;
/// Worker threads of the server: a browser opens up to six connections to one host.
constexpr std::size_t ServerThreads = 8;
/// At most this many relMSE points are kept (every other one is dropped beyond).
constexpr std::size_t MaxHistory = 4096;

/// The image as the page shows it before exposure: linear sRGB (3 channels) or grey (1).
struct Snapshot {
    int width = 0, height = 0, channels = 0;
    std::vector<float> linear;
};

/// R, G, B as linear sRGB (a film in another RGB space looks slightly off here, and only
/// here), X, Y, Z converted to it, else the luminance Y or the first channel as grey.
Snapshot displayLinear(const Image& img) {
    const auto channel = [&](const char* name) {
        auto it = std::find(img.channelNames.begin(), img.channelNames.end(), name);
        return it == img.channelNames.end() ? -1 : int(it - img.channelNames.begin());
    };
    const int r = channel("R"), g = channel("G"), b = channel("B"), x = channel("X"), y = channel("Y"),
              z = channel("Z");
    const bool rgb = r >= 0 && g >= 0 && b >= 0, xyz = !rgb && x >= 0 && y >= 0 && z >= 0;
    Snapshot s{img.width, img.height, rgb || xyz ? 3 : 1, {}};
    const int nc = img.channels(), grey = std::max(y, 0);
    if (nc == 0 || img.width <= 0 || img.height <= 0) return {};
    const std::size_t pixels = std::size_t(img.width) * std::size_t(img.height);
    s.linear.resize(pixels * std::size_t(s.channels));
    for (std::size_t i = 0; i < pixels; ++i) {
        const float* p = img.pixels.data() + i * std::size_t(nc);
        float* d = s.linear.data() + i * std::size_t(s.channels);
        if (s.channels == 1) {
            d[0] = p[grey];
            continue;
        }
        const Vector3f v = rgb ? Vector3f(p[r], p[g], p[b]) : xyzToLinearSRGB(Vector3f(p[x], p[y], p[z]));
        d[0] = v.x, d[1] = v.y, d[2] = v.z;
    }
    return s;
}

std::string jsonNumber(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : "null"; }

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') out += '\\', out += char(c);
        else if (c < 0x20) out += fmt::format("\\u{:04x}", c);
        else out += char(c);
    }
    return out + "\"";
}

class HttpPreview final : public Preview {
public:
    HttpPreview(int port, PreviewJob job) : m_job(std::move(job)) {
        m_server.new_task_queue = [] { return new httplib::ThreadPool(ServerThreads); };
        m_server.set_keep_alive_timeout(2);
        m_server.Get("/", [this](const httplib::Request&, httplib::Response& res) {
            touch();
            res.set_content(PreviewPage, "text/html; charset=utf-8");
        });
        m_server.Get("/status.json", [this](const httplib::Request&, httplib::Response& res) {
            touch();
            res.set_header("Cache-Control", "no-store");
            res.set_content(statusJson(), "application/json");
        });
        m_server.Get("/image.png", [this](const httplib::Request& req, httplib::Response& res) { image(req, res); });
        errno = 0;
        m_port = port == 0 ? m_server.bind_to_any_port("127.0.0.1")
                           : (m_server.bind_to_port("127.0.0.1", port) ? port : -1);
        if (m_port <= 0)
            fail("--preview: cannot listen on 127.0.0.1:{}: {}", port, errno ? std::strerror(errno) : "bind failed");
        m_thread = std::thread([this] { m_server.listen_after_bind(); });
    }

    ~HttpPreview() override {
        m_server.stop();
        if (m_thread.joinable()) m_thread.join();
    }

    int port() const override { return m_port; }

    void afterPass(const Scene& scene, const PassReport& report, double* maxPassSeconds) override {
        if (!publish(scene, report, false) || !maxPassSeconds) return;
        if (m_ownPassSeconds < 0.0) m_ownPassSeconds = *maxPassSeconds;
        const double watched =
            m_ownPassSeconds > 0.0 ? std::min(m_ownPassSeconds, WatchedPassSeconds) : WatchedPassSeconds;
        *maxPassSeconds = this->watched() ? watched : m_ownPassSeconds;
    }

    void finish(const Scene& scene, const PassReport& last) override {
        if (!publish(scene, last, true) || last.stats.interrupted || !watched()) return;
        std::unique_lock lock(m_mutex);
        m_served.wait_for(lock, std::chrono::seconds(3), [&] { return m_servedFrame >= m_frame; });
    }

private:
    void touch() { m_lastRequest.store(Clock::now().time_since_epoch().count()); }
    bool watched() const {
        const Clock::time_point last{Clock::duration(m_lastRequest.load())};
        return m_lastRequest.load() != 0 && Clock::now() - last < WatchWindow;
    }

    /// In the render thread, between passes (or after the last): nothing writes the film.
    /// False once it has failed (said once): the page then stays as it was.
    bool publish(const Scene& scene, const PassReport& report, bool done) noexcept {
        if (m_failed) return false;
        try {
            copy(scene, report, done);
            return true;
        } catch (const std::exception& e) {
            m_failed = true;
            log::warn("preview: the page is no longer updated: {}", e.what());
            return false;
        }
    }

    void copy(const Scene& scene, const PassReport& report, bool done) {
        const Image img = scene.camera().film().develop();
        auto snapshot = std::make_shared<const Snapshot>(displayLinear(img));
        double estimate = report.estimatedRelMSE;
        std::vector<float> variance;
        if (estimate < 0.0 && scene.renderer().varianceEstimate(variance)) estimate = estimatedRelMSE(img, variance);
        if (!std::isfinite(estimate)) estimate = -1.0;  // one sample per pixel tells no variance
        std::lock_guard lock(m_mutex);
        m_image = std::move(snapshot);
        ++m_frame;
        m_report = report;
        m_report.estimatedRelMSE = estimate;
        m_done = done;
        if (estimate > 0.0 && report.seconds > 0.0 && (m_history.empty() || report.seconds > m_history.back().first))
            m_history.emplace_back(report.seconds, estimate);
        if (m_history.size() > MaxHistory) {  // keep every other point
            std::size_t kept = 0;
            for (std::size_t i = 0; i < m_history.size(); i += 2) m_history[kept++] = m_history[i];
            m_history.resize(kept);
        }
    }

    std::string statusJson() {
        std::lock_guard lock(m_mutex);
        const PassReport& r = m_report;
        const double e = r.estimatedRelMSE >= 0.0 ? r.estimatedRelMSE : NAN;
        // The fraction done by each budget: samples, seconds, and for a noise target the
        // samples needed under relMSE ∝ 1/spp (target / current). The first reached ends it.
        double progress = NAN;
        const auto reach = [&](double f) { progress = std::isnan(progress) ? f : std::max(progress, f); };
        if (m_job.spp > 0) reach(double(r.spp) / double(m_job.spp));
        if (m_job.timeBudget > 0.0) reach(r.seconds / m_job.timeBudget);
        if (m_job.targetRelMSE > 0.0 && e > 0.0) reach(m_job.targetRelMSE / e);
        progress = m_done && !r.stats.interrupted ? 1.0 : std::min(progress, 1.0);
        const double eta = progress > 0.0 ? r.seconds * (1.0 - progress) / progress : NAN;
        std::string history;
        for (const auto& [t, v] : m_history)
            history += fmt::format("{}[{},{}]", history.empty() ? "" : ",", jsonNumber(t), jsonNumber(v));
        return fmt::format(
            "{{\"scene\":{},\"renderer\":{},\"width\":{},\"height\":{},\"frame\":{},\"spp\":{},\"seconds\":{},"
            "\"samples\":{},\"samplesPerSecond\":{},\"progress\":{},\"eta\":{},\"relmse\":{},"
            "\"target\":{{\"spp\":{},\"seconds\":{},\"relmse\":{}}},\"done\":{},\"interrupted\":{},\"history\":[{}]}}",
            jsonString(m_job.scene), jsonString(m_job.renderer), m_image ? m_image->width : 0,
            m_image ? m_image->height : 0, m_frame, r.spp, jsonNumber(r.seconds), r.stats.samples,
            jsonNumber(r.seconds > 0.0 ? double(r.stats.samples) / r.seconds : NAN), jsonNumber(progress),
            jsonNumber(eta), jsonNumber(e), m_job.spp, jsonNumber(m_job.timeBudget), jsonNumber(m_job.targetRelMSE),
            m_done, r.stats.interrupted, history);
    }

    void image(const httplib::Request& req, httplib::Response& res) {
        touch();
        res.set_header("Cache-Control", "no-store");
        std::shared_ptr<const Snapshot> snapshot;
        std::uint64_t frame = 0;
        {
            std::lock_guard lock(m_mutex);
            snapshot = m_image, frame = m_frame;
        }
        if (!snapshot || snapshot->linear.empty()) {
            res.status = 503;
            res.set_content("no image yet: the first pass is still rendering", "text/plain");
            return;
        }
        float exposure = 0.f;
        try {
            if (req.has_param("exposure")) exposure = std::stof(req.get_param_value("exposure"));
        } catch (const std::exception&) {
        }
        exposure = std::isfinite(exposure) ? std::clamp(exposure, -32.f, 32.f) : 0.f;
        const ToneMap toneMap = tonemap::parse(req.get_param_value("tonemap")).value_or(ToneMap::None);
        const std::string key = fmt::format("{} {} {}", frame, exposure, int(toneMap));
        {
            std::lock_guard lock(m_pngMutex);
            if (key != m_pngKey) {
                const Snapshot& s = *snapshot;
                m_png = hdrfilm_io::encodePngBytes(s.width, s.height, s.channels,
                                                   hdrfilm_io::displayBytes(s.channels, s.linear, exposure, toneMap));
                m_pngKey = key;
            }
            res.set_content(m_png, "image/png");
        }
        {
            std::lock_guard lock(m_mutex);
            m_servedFrame = std::max(m_servedFrame, frame);
        }
        m_served.notify_all();
    }

    const PreviewJob m_job;
    httplib::Server m_server;
    std::thread m_thread;
    int m_port = 0;
    std::atomic<Clock::rep> m_lastRequest{0};  // steady clock ticks; 0: never
    double m_ownPassSeconds = -1.0;            // the render's own pass limit (render thread only)
    bool m_failed = false;                     // publish() failed once (render thread only)

    std::mutex m_mutex;  // guards what follows
    std::condition_variable m_served;
    std::shared_ptr<const Snapshot> m_image;
    std::uint64_t m_frame = 0, m_servedFrame = 0;
    PassReport m_report;
    bool m_done = false;
    std::vector<std::pair<double, double>> m_history;  // (seconds, estimated relMSE)

    std::mutex m_pngMutex;  // the last PNG encoded, for its frame, exposure and tone map
    std::string m_pngKey, m_png;
};

} // namespace

} // namespace effigi::app

extern "C" __attribute__((visibility("default"))) effigi::app::Preview*
effigiStartPreview(int port, const effigi::app::PreviewJob& job, std::string& error) noexcept {
    // Nothing may unwind through dlsym'ed C linkage: failures become a message.
    try {
        error.clear();
        return new effigi::app::HttpPreview(port, job);
    } catch (const std::exception& e) {
        error = e.what();
    } catch (...) {
        error = "--preview: the server could not start";
    }
    return nullptr;
}

// The entry point's type is the one preview_load.cpp casts dlsym's result to.
static_assert(std::is_same_v<decltype(&effigiStartPreview), effigi::app::preview_module::Start>);

#pragma once
// For tests/test_preview.cpp: an `effigi render --preview 0` running in the background
// (its output in a file, where it says its port), a plain HTTP/1.0 GET on the loopback
// interface, and a number out of the preview's status JSON.
#include <arpa/inet.h>
#include <csignal>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace effigi::test {

/// The effigi executable run with `args`, stdout and stderr into `log`; killed if the
/// test leaves without waiting for it.
class BackgroundApp {
public:
    BackgroundApp(const std::vector<std::string>& args, std::filesystem::path log) : m_log(std::move(log)) {
        m_pid = fork();
        if (m_pid == 0) {
            const int fd = open(m_log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            dup2(fd, 1), dup2(fd, 2);
            std::vector<char*> argv{const_cast<char*>(EFFIGI_APP)};
            for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            execv(EFFIGI_APP, argv.data());
            _exit(127);
        }
    }
    ~BackgroundApp() {
        if (m_pid > 0) kill(m_pid, SIGKILL), waitpid(m_pid, nullptr, 0);
    }
    BackgroundApp(const BackgroundApp&) = delete;
    BackgroundApp& operator=(const BackgroundApp&) = delete;

    std::string output() const {
        std::ifstream in(m_log);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    /// The port of "preview: http://127.0.0.1:PORT/" once printed (0 after `seconds`, or
    /// when the process ended first).
    int port(double seconds = 20.0) {
        static const std::regex url(R"(preview: http://127\.0\.0\.1:(\d+)/)");
        const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (std::chrono::steady_clock::now() < end) {
            std::smatch m;
            const std::string out = output();
            if (std::regex_search(out, m, url)) return std::stoi(m[1]);
            if (m_pid > 0 && waitpid(m_pid, &m_status, WNOHANG) == m_pid) return m_pid = -1, 0;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return 0;
    }
    /// SIGINT (a render stops after writing its image) and the exit code.
    int interrupt() {
        if (m_pid > 0) kill(m_pid, SIGINT);
        return wait();
    }
    int wait() {
        if (m_pid > 0) waitpid(m_pid, &m_status, 0), m_pid = -1;
        return WIFEXITED(m_status) ? WEXITSTATUS(m_status) : -1;
    }

private:
    std::filesystem::path m_log;
    pid_t m_pid = -1;
    int m_status = 0;
};

struct HttpReply {
    int status = 0;  // 0: no answer
    std::string contentType, body;
};

/// GET http://127.0.0.1:port/path over HTTP/1.0 (the server closes after the answer).
inline HttpReply httpGet(int port, const std::string& path) {
    HttpReply r;
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(std::uint16_t(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    timeval timeout{10, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) return close(fd), r;
    const std::string request = "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
    send(fd, request.data(), request.size(), MSG_NOSIGNAL);
    std::string raw;
    char buf[1 << 16];
    for (ssize_t n; (n = recv(fd, buf, sizeof buf, 0)) > 0;) raw.append(buf, std::size_t(n));
    close(fd);
    const std::size_t end = raw.find("\r\n\r\n");
    if (raw.rfind("HTTP/1.", 0) != 0 || end == std::string::npos) return r;
    r.status = std::atoi(raw.c_str() + 9);
    static const std::regex type(R"(\r\nContent-Type: ([^\r]*))", std::regex::icase);
    std::smatch m;
    const std::string head = raw.substr(0, end);
    if (std::regex_search(head, m, type)) r.contentType = m[1];
    r.body = raw.substr(end + 4);
    return r;
}

/// The number `"key":value` in a JSON text (NaN when absent or null).
inline double jsonNumber(const std::string& json, const std::string& key) {
    const std::regex field("\"" + key + R"(":(-?[0-9.eE+-]+))");
    std::smatch m;
    return std::regex_search(json, m, field) ? std::stod(m[1]) : NAN;
}

/// The [seconds, relMSE] pairs of the status's "history".
inline std::vector<std::pair<double, double>> jsonHistory(const std::string& json) {
    std::vector<std::pair<double, double>> points;
    const std::size_t at = json.find("\"history\":[");
    if (at == std::string::npos) return points;
    static const std::regex pair(R"(\[([-0-9.eE+]+),([-0-9.eE+]+)\])");
    const std::string rest = json.substr(at);
    for (std::sregex_iterator it(rest.begin(), rest.end(), pair), end; it != end; ++it)
        points.emplace_back(std::stod((*it)[1]), std::stod((*it)[2]));
    return points;
}

} // namespace effigi::test

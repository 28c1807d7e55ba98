// The replay driver: a fuzz target built as an ordinary program, without libFuzzer and
// without clang, so that `make test` (the release build, gcc) runs every target on its
// committed seeds and on tests/data/regressions/<target>/ (inputs that once crashed or
// hung). Shared by all targets: each is linked with this main instead of libFuzzer's.
//
//   fuzz_<target>_replay <file or folder>...
//
// Folders are read recursively (files whose names start with '.' are skipped: .gitkeep),
// in sorted order, each file once through LLVMFuzzerTestOneInput, as libFuzzer runs a file
// given on its command line. A finding ends the program as it would end the fuzzer: a
// crash, an abort from the target's checks, or an uncaught exception (std::terminate).
// The name of each input is printed before it runs, so a failing run says which one.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
// Optional in a target, as in libFuzzer.
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) __attribute__((weak));

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s <file or folder>...\n", argv[0]);
        return 2;
    }
    std::vector<fs::path> inputs;
    for (int i = 1; i < argc; ++i) {
        const fs::path arg = argv[i];
        std::error_code ec;
        if (fs::is_regular_file(arg, ec)) {
            inputs.push_back(arg);
        } else if (fs::is_directory(arg, ec)) {
            std::vector<fs::path> found;
            for (const fs::directory_entry& e : fs::recursive_directory_iterator(arg, ec))
                if (e.is_regular_file() && e.path().filename().string()[0] != '.') found.push_back(e.path());
            std::sort(found.begin(), found.end());
            inputs.insert(inputs.end(), found.begin(), found.end());
        } else {
            std::fprintf(stderr, "%s: no such file or folder\n", arg.c_str());  // a typo must not pass as "nothing to do"
            return 2;
        }
    }
    if (LLVMFuzzerInitialize) LLVMFuzzerInitialize(&argc, &argv);
    for (const fs::path& p : inputs) {
        std::fprintf(stderr, "replay %s\n", p.c_str());
        std::ifstream in(p, std::ios::binary);
        if (!in) {
            std::fprintf(stderr, "%s: cannot read\n", p.c_str());
            return 2;
        }
        const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    }
    std::fprintf(stderr, "replayed %zu inputs: no findings\n", inputs.size());
    return 0;
}

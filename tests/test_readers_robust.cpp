// Every file reader against hostile input (issue 12): paths that are not regular files
// (/dev/zero, a FIFO, a folder) are refused with one line naming the scene line and the
// path, instead of reading forever or blocking; declared counts cannot drive work past
// the file's real size; and errors that quote the input quote it escaped and short
// (excerpt()), so that no message spans lines or carries control bytes.
#include "printable_line.hpp"
#include "app_runner.hpp"
#include "shape_helpers.hpp"
#include "temp_files.hpp"
#include "xml_helpers.hpp"

#include "effigi/core/input.hpp"
#include "effigi/render/ply_reader.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <sys/stat.h>
#include <vector>

using namespace effigi;
using namespace effigi::test;
using Catch::Contains;
namespace fs = std::filesystem;

namespace {

const ScratchDir scratch("readers_robust");

/// A FIFO in the scratch folder: opening it to read would block until a writer comes.
fs::path fifo() {
    static const fs::path p = [] {
        fs::path f = scratch.dir() / "fifo";
        REQUIRE(::mkfifo(f.c_str(), 0600) == 0);
        return f;
    }();
    return p;
}


/// The message of parsing, then instantiating every top-level object of, the scene
/// `xml` written as scene.xml in the scratch folder.
std::string sceneError(const std::string& xml) {
    fs::path file = scratch.write("scene.xml", xml);
    std::string msg = errorOf([&] {
        auto root = xml::parseFile(file);
        for (const auto& c : root->children) instantiate(*c.node, Registry::instance());
    });
    INFO("message: " << msg);
    CHECK(printableLine(msg));
    return msg;
}

/// A one-object scene whose object (on line 2) names `path` on line 3.
std::string objectNaming(const std::string& tag, const std::string& type, const fs::path& path) {
    return fmt::format("<scene version=\"3.0.0\">\n<{} type=\"{}\">\n<string name=\"filename\" value=\"{}\"/>\n</{}>\n"
                       "</scene>\n",
                       tag, type, path.string(), tag);
}

/// The paths no reader may read: a device that never ends, a FIFO, a folder.
std::vector<std::pair<fs::path, std::string>> notRegularFiles() {
    std::vector<std::pair<fs::path, std::string>> v;
    if (fs::exists("/dev/zero")) v.emplace_back("/dev/zero", "a character device");
    v.emplace_back(fifo(), "a FIFO");
    v.emplace_back(scratch.dir(), "a directory");
    return v;
}

} // namespace

TEST_CASE("excerpt: input is quoted escaped, as one printable line, and cut", "[readers]") {
    CHECK(excerpt("plain text 1.5") == "plain text 1.5");
    CHECK(excerpt("a\nb\tc\rd\\e") == "a\\nb\\tc\\rd\\\\e");
    CHECK(excerpt(std::string("\x01\x1b[31m\x7f\0", 8)) == "\\x01\\x1B[31m\\x7F\\x00");
    // Valid UTF-8 is kept; invalid bytes, overlong forms and surrogates are escaped, as
    // are the C1 control NEL and the line separator U+2028.
    CHECK(excerpt("\xce\xbb = 550 nm \xe2\x80\x94 ok") == "\xce\xbb = 550 nm \xe2\x80\x94 ok");
    CHECK(excerpt("\xff\xfe") == "\\xFF\\xFE");
    CHECK(excerpt("\xc0\xaf") == "\\xC0\\xAF");
    CHECK(excerpt("\xed\xa0\x80") == "\\xED\\xA0\\x80");
    CHECK(excerpt("x\xc3") == "x\\xC3");  // a sequence cut short by the end of the text
    CHECK(excerpt("\xc2\x85|\xe2\x80\xa8") == "\\xC2\\x85|\\xE2\\x80\\xA8");
    // Cut after maxChars characters (an escape or a multi-byte character counts as one).
    CHECK(excerpt(std::string(40, 'a')) == std::string(40, 'a'));
    CHECK(excerpt(std::string(41, 'a')) == std::string(40, 'a') + "\xe2\x80\xa6");
    CHECK(excerpt(std::string(100, '\n'), 3) == "\\n\\n\\n\xe2\x80\xa6");
    CHECK(excerpt("\xce\xbb\xce\xbb\xce\xbb", 2) == "\xce\xbb\xce\xbb\xe2\x80\xa6");
    // Every byte value, alone and after a lead byte, gives a printable line.
    for (int b = 0; b < 256; ++b) {
        INFO("byte " << b);
        CHECK(printableLine(excerpt(std::string(1, char(b)))));
        CHECK(printableLine(excerpt(std::string("\xe2") + char(b) + "\x80")));
    }
}

TEST_CASE("readers: devices, FIFOs and folders are refused naming the scene line and the path", "[readers]") {
    struct Reader {
        const char* tag;
        const char* type;
    };
    // Every component that reads a file named by its 'filename' parameter.
    const Reader readers[] = {{"shape", "ply"},         {"shape", "obj"},      {"shape", "serialized"},
                              {"shape", "linearcurve"}, {"shape", "bsplinecurve"}, {"shape", "sdfgrid"},
                              {"texture", "bitmap"},    {"emitter", "envmap"}};
    for (const auto& [path, kind] : notRegularFiles()) {
        for (const Reader& r : readers) {
            INFO(r.type << " reading " << path.string());
            std::string msg = sceneError(objectNaming(r.tag, r.type, path));
            CHECK_THAT(msg, Contains("scene.xml:3:"));
            CHECK_THAT(msg, Contains(path.string()));
            CHECK_THAT(msg, Contains("it is " + kind));
        }
    }
}

TEST_CASE("readers: an included or spectrum file that is not a regular file is refused", "[readers]") {
    for (const auto& [path, kind] : notRegularFiles()) {
        INFO(path.string());
        std::string inc = sceneError(fmt::format("<scene version=\"3.0.0\">\n\n<include filename=\"{}\"/>\n</scene>\n",
                                                 path.string()));
        CHECK_THAT(inc, Contains("scene.xml:3:"));
        CHECK_THAT(inc, Contains(path.string()));
        CHECK_THAT(inc, Contains("it is " + kind));
        std::string spd = sceneError(fmt::format("<scene version=\"3.0.0\">\n<bsdf type=\"conductor\">\n"
                                                 "<spectrum name=\"eta\" filename=\"{}\"/>\n</bsdf>\n</scene>\n",
                                                 path.string()));
        CHECK_THAT(spd, Contains("scene.xml:3:"));
        CHECK_THAT(spd, Contains("eta"));
        CHECK_THAT(spd, Contains(path.string()));
        CHECK_THAT(spd, Contains("it is " + kind));
    }
    // The top-level scene file too.
    for (const auto& [path, kind] : notRegularFiles()) {
        std::string msg = errorOf([&] { xml::parseFile(path); });
        CHECK_THAT(msg, Contains(path.string()));
        CHECK_THAT(msg, Contains("it is " + kind));
    }
}

TEST_CASE("cli: a reference image that is not a regular file is refused with one line", "[readers][cli]") {
    const std::string plane = EFFIGI_SOURCE_DIR "/tests/data/converge/plane.xml";
    for (const auto& [path, kind] : notRegularFiles()) {
        AppResult r = runApp(fmt::format("converge {} --reference {} --spp 1 --out {} -D res=8 -D spp=1 --no-progress",
                                         plane, path.string(), (scratch.dir() / "conv").string()));
        INFO(r.out);
        CHECK(r.exitCode == 1);
        CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
        CHECK_THAT(r.out, Contains(path.string() + ": cannot read image: it is " + kind));
    }
}

TEST_CASE("ply: declared counts are bounded by the bytes the file holds", "[readers][ply]") {
    const std::string mesh = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face 1\nproperty list uchar int vertex_indices\n";
    const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    SECTION("an element without properties holds no bytes: skipped whatever its count") {
        // Mitsuba 3 seeks past count x 0 bytes; reading it record by record never ends.
        const std::string empty = "element nothing 18446744073709551615\n";
        CHECK(readPlyFromMemory("ply\nformat ascii 1.0\n" + empty + mesh + "end_header\n" + body, "e.ply")
                  .triangleCount() == 1);
        CHECK(readPlyFromMemory("ply\nformat ascii 1.0\n" + mesh + empty + "end_header\n" + body, "e.ply")
                  .triangleCount() == 1);
        CHECK(readPlyFromMemory("ply\nformat binary_little_endian 1.0\n" + empty + "end_header\n", "e.ply")
                  .triangleCount() == 0);
    }
    SECTION("a count the rest of the file cannot hold is an error naming file, line, element and count") {
        for (const std::string format : {"ascii", "binary_big_endian"}) {
            INFO(format);
            // The binary body holds the mesh's 37 bytes at least, not the junk records.
            std::string data = fmt::format("ply\nformat {} 1.0\n{}element junk 1000000000000\nproperty uchar a\n"
                                           "end_header\n{}",
                                           format, mesh, format == "ascii" ? body : std::string(64, '\0'));
            std::string msg = errorOf([&] { readPlyFromMemory(data, "huge.ply"); });
            INFO(msg);
            CHECK_THAT(msg, Contains("huge.ply:9:"));
            CHECK_THAT(msg, Contains("'junk'"));
            CHECK_THAT(msg, Contains("1000000000000"));
            CHECK_THAT(msg, Contains("more than the rest of the file can hold"));
        }
        // 2^64 - 1 vertices, read through the ply shape: the same error.
        fs::path p = scratch.write("huge.ply", "ply\nformat ascii 1.0\nelement vertex 18446744073709551615\n"
                                               "property float x\nproperty float y\nproperty float z\nend_header\n" +
                                                   body);
        std::string msg = sceneError(objectNaming("shape", "ply", p));
        CHECK_THAT(msg, Contains("scene.xml:3:"));
        CHECK_THAT(msg, Contains("huge.ply:3:"));
        CHECK_THAT(msg, Contains("18446744073709551615"));
        CHECK_THAT(msg, Contains("more than the rest of the file can hold"));
    }
}

TEST_CASE("readers: errors quoting the input quote it escaped and short", "[readers]") {
    // 61 characters of content with a line break, a tab, an escape, DEL and invalid
    // UTF-8: quoted as escapes, cut after 40 characters. Line-based files cannot hold a
    // newline inside a line, so theirs has a carriage return.
    const std::string tail = std::string("line\twith\x1b\x7f\xff") + std::string(45, 'x');
    const std::string junk = "bad\n" + tail, junkLine = "bad\r" + tail;
    const std::string quotedTail = "line\\twith\\x1B\\x7F\\xFF";  // 12 characters
    auto expectQuoted = [&](const std::string& msg, const std::string& quoted) {
        INFO("message: " << msg);
        CHECK(printableLine(msg));
        CHECK_THAT(msg, Contains(quoted));
        CHECK_THAT(msg, !Contains(std::string(30, 'x')));
    };
    const std::string ellipsis = "\xe2\x80\xa6";
    SECTION("xml text") {
        std::string msg = errorOf([&] {
            xml::parseString("<scene version=\"3.0.0\">\n<shape type=\"sphere\">" + junk + "</shape>\n</scene>",
                             "t.xml");
        });
        CHECK_THAT(msg, Contains("t.xml:2:"));
        expectQuoted(msg, "'bad\\n" + quotedTail + std::string(24, 'x') + ellipsis + "'");
        msg = errorOf([&] { xml::parseString("<scene version=\"3.0.0\">" + junk + "</scene>", "t.xml"); });
        expectQuoted(msg, "'bad\\n" + quotedTail + std::string(24, 'x') + ellipsis + "'");
    }
    SECTION("xml attribute values (character references reach the value unnormalised)") {
        std::string msg = errorOf([&] {
            xml::parseString("<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n"
                             "<float name=\"radius\" value=\"1&#10;2&#9;\x01\"/>\n</shape>\n</scene>",
                             "t.xml");
        });
        INFO(msg);
        CHECK(printableLine(msg));
        CHECK_THAT(msg, Contains("t.xml:3:"));
        CHECK_THAT(msg, Contains("'1\\n2\\t\\x01'"));
        msg = errorOf([&] { xml::parseString("<scene version=\"3&#10;0\"/>", "t.xml"); });
        CHECK(printableLine(msg));
        CHECK_THAT(msg, Contains("'3\\n0'"));
    }
    SECTION(".spd file lines") {
        fs::path spd = scratch.write("junk.spd", "400 1\n" + junkLine + " 2\n");
        std::string msg = sceneError(fmt::format("<scene version=\"3.0.0\">\n<bsdf type=\"conductor\">\n"
                                                 "<spectrum name=\"eta\" filename=\"{}\"/>\n</bsdf>\n</scene>\n",
                                                 spd.string()));
        CHECK_THAT(msg, Contains("scene.xml:3:"));
        CHECK_THAT(msg, Contains("junk.spd:2:"));
        expectQuoted(msg, "'bad\\r" + quotedTail + std::string(24, 'x') + ellipsis + "'");
    }
    SECTION("PLY header lines and tokens") {
        std::string msg =
            errorOf([&] { readPlyFromMemory("ply\nformat ascii 1.0 " + junkLine + "\nend_header\n", "q.ply"); });
        CHECK_THAT(msg, Contains("q.ply:2:"));
        expectQuoted(msg, "'format ascii 1.0 bad\\r" + quotedTail + std::string(7, 'x') + ellipsis + "'");
        msg = errorOf([&] { readPlyFromMemory("ply\nformat ascii 1.0\n" + junkLine + "\nend_header\n", "q.ply"); });
        CHECK(printableLine(msg));
        CHECK_THAT(msg, Contains("'bad\\rline'"));
        msg = errorOf([&] {
            readPlyFromMemory("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                              "property float z\nend_header\n0 0 \x01" + std::string(60, 'y') + "\n",
                              "q.ply");
        });
        CHECK(printableLine(msg));
        CHECK_THAT(msg, Contains("'\\x01" + std::string(39, 'y') + "\xe2\x80\xa6'"));
    }
    SECTION("curve files") {
        fs::path curve = scratch.write("junk.txt", "0 0 0 1\n1 1 1 1 " + junkLine + "\n");
        std::string msg = sceneError(objectNaming("shape", "linearcurve", curve));
        CHECK_THAT(msg, Contains("junk.txt:2:"));
        expectQuoted(msg, "'1 1 1 1 bad\\r" + quotedTail + std::string(16, 'x') + ellipsis + "'");
    }
}

#pragma once
// Internal to the PLY reader (ply_reader.cpp): the header's description of the file —
// value types, elements and their properties (ply_header.cpp) — and how an element's
// extra scalar properties group into mesh attributes as Mitsuba 3 names them
// (ply_attributes.cpp).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace effigi::ply {

enum class Type { I8, U8, I16, U16, I32, U32, I64, U64, F32, F64 };
enum class Format { Ascii, BinaryLE, BinaryBE };

inline bool isInteger(Type t) { return t != Type::F32 && t != Type::F64; }
std::size_t typeSize(Type t);
/// Integer attribute values divided by the type's largest value (uchar colours 0-255
/// -> [0, 1]).
double normalizedInteger(Type t, double v);

struct Property {
    std::string name;
    Type type = Type::F32;
    bool list = false;
    Type countType = Type::U8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> props;
    int line = 0;  // header line declaring it
};

/// What the header says, and where the body starts.
struct Header {
    Format format = Format::Ascii;
    std::vector<Element> elements;
    std::size_t bodyPos = 0;  // byte offset of the body
    int bodyLine = 0;         // line of the body's start (meaningful for ascii)
};

/// Parse the header of the PLY data `data`; errors name `name` and the header line.
Header parseHeader(std::string_view data, const std::string& name);

/// One attribute: its mesh name and the indices of the properties holding its channels.
struct AttrGroup {
    std::string name;
    std::vector<std::size_t> props;
};

/// The attributes among element e's scalar properties not `taken` (Mitsuba's
/// find_other_fields), named with `prefix` ("vertex_" or "face_"); what cannot be
/// grouped is warned about, naming the file `fileName`, and skipped.
std::vector<AttrGroup> attributeGroups(const Element& e, const std::string& prefix, std::vector<bool> taken,
                                       const std::string& fileName);

} // namespace effigi::ply

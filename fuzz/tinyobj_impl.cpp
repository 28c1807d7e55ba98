// tinyobjloader's implementation, compiled into the `obj` module of the fuzz build only
// (fuzz/CMakeLists.txt): Debian's libtinyobjloader.so is not instrumented, so without this
// the fuzzer would see none of the OBJ parser's branches and AddressSanitizer none of its
// memory accesses. Same version as the shared library (one Debian package ships both).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>

// What the mesh readers in C++ (sam_mesh_openmesh.cpp, sam_mesh_gltf.cpp)
// share: a vector copied out to memory C frees, and a read run with every
// exception turned into one error line, so none crosses into C.
#ifndef SAM_MESH_CPP_HPP
#define SAM_MESH_CPP_HPP

#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "sam_mesh_soup.h"

// A malloc'd copy of `v` (one byte for an empty one); throws bad_alloc.
template <class T> T *sam_mesh_copy_out(const std::vector<T> &v)
{
    T *p = static_cast<T *>(std::malloc(v.empty() ? 1 : v.size() * sizeof(T)));
    if (!p)
        throw std::bad_alloc();
    if (!v.empty())
        std::memcpy(p, v.data(), v.size() * sizeof(T));
    return p;
}

// A library's message as one line: line ends become spaces, trailing
// spaces go.
inline std::string sam_mesh_one_line(std::string s)
{
    for (char &c : s)
        if (c == '\n' || c == '\r')
            c = ' ';
    while (!s.empty() && s.back() == ' ')
        s.pop_back();
    return s;
}

// read(), which returns a sam_status; an exception becomes
// SAM_ERR_OUT_OF_MEMORY or SAM_ERR_FORMAT naming `path` and `library`.
template <class Read> sam_status sam_mesh_guarded(const char *path, const char *library, sam_error *err, Read read)
{
    try {
        return read();
    } catch (const std::bad_alloc &) {
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory while reading", path);
    } catch (const std::exception &e) {
        return sam_fail(err, SAM_ERR_FORMAT, "%s: %s failed: %s", path, library, e.what());
    } catch (...) {
        return sam_fail(err, SAM_ERR_FORMAT, "%s: %s failed with an unknown exception", path, library);
    }
}

#endif

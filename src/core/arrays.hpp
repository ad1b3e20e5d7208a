// Array types and helpers shared by the core's bindings: nanobind views of the caller's
// C-contiguous CPU arrays, new numpy arrays that own their memory, and the ValueError a
// binding raises when an argument does not fit.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstddef>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace optri::arrays {

namespace nb = nanobind;

// A read-only view of the caller's array (never converted: a mismatch is a TypeError).
template <class T>
using In = nb::ndarray<const T, nb::c_contig, nb::device::cpu>;
// A writable view of the caller's array (filled in place).
template <class T>
using Out = nb::ndarray<T, nb::c_contig, nb::device::cpu>;
// A new numpy array handed back to Python.
template <class T>
using NewArray = nb::ndarray<nb::numpy, T>;

// Raise ValueError("<module>: <what>") unless ok.
inline void need(bool ok, const char* module, const char* what) {
    if (!ok) throw std::invalid_argument(std::string(module) + ": " + what);
}

// A numpy array of this shape over data, which it owns from now on (moved, not copied).
template <class T>
NewArray<T> owning(std::vector<T>&& data, std::initializer_list<size_t> shape) {
    auto* heap = new std::vector<T>(std::move(data));
    nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    return NewArray<T>(heap->data(), shape, owner);
}

// A new zeroed numpy array of this shape.
template <class T>
NewArray<T> zeros(std::initializer_list<size_t> shape) {
    size_t total = 1;
    for (size_t s : shape) total *= s;
    T* data = new T[total > 0 ? total : 1]();
    nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<T*>(p); });
    return NewArray<T>(data, shape, owner);
}

}  // namespace optri::arrays

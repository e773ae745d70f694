// rtdenoise — how settings structs describe their fields. A struct lists its fields once in
// `template <class V> void visit(V& v)`, as `v("name", field, "doc")` (optionally with a Range,
// or for an enum with its choices); the library uses that to list and set fields by name.
#pragma once
#include <initializer_list>

namespace rtd {

/// Inclusive range a numeric setting must lie in.
struct Range {
  double lo, hi;
};

/// Names of an enum's values, in order of the enum's underlying values 0, 1, 2, ...
using Choices = std::initializer_list<const char*>;

}  // namespace rtd

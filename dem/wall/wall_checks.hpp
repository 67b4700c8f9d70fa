#pragma once
// Input validation shared by the wall constructors. Each check throws
// std::invalid_argument with the message "<where>: <what>", `where` being the
// wall's name ("plane wall", "cone wall", ...). `where` is a plain C string so
// walls built during static initialization can still throw.

#include "dem/vec3.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace demcal::dem::wall_checks {

[[noreturn]] inline void fail(const char* where, const std::string& what) {
  throw std::invalid_argument(std::string(where) + ": " + what);
}

inline Vec3 checked_point(const char* where, const Vec3& p, const char* param) {
  if (!is_finite(p)) fail(where, std::string(param) + " must be finite");
  return p;
}

// The normalized vector; it must be finite and non-zero.
inline Vec3 checked_unit(const char* where, const Vec3& v, const char* param) {
  if (!is_finite(v) || !(norm2(v) > 0.0)) {
    std::ostringstream msg;
    msg << param << " must be a non-zero finite vector (got [" << v.x << ", " << v.y << ", "
        << v.z << "])";
    fail(where, msg.str());
  }
  return normalized(v);
}

inline double checked_positive(const char* where, double x, const char* param) {
  if (!(x > 0.0) || !std::isfinite(x)) {
    std::ostringstream msg;
    msg << param << " must be > 0 (got " << x << ")";
    fail(where, msg.str());
  }
  return x;
}

inline double checked_non_negative(const char* where, double x, const char* param) {
  if (!(x >= 0.0) || !std::isfinite(x)) {
    std::ostringstream msg;
    msg << param << " must be >= 0 (got " << x << ")";
    fail(where, msg.str());
  }
  return x;
}

}  // namespace demcal::dem::wall_checks

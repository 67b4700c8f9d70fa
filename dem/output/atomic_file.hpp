#pragma once
// dem's output goes through demcal's one atomic writer (io/atomic_file.hpp):
// a crash or a full disk leaves the previous file or none, never a truncated
// one that a reader (ParaView, a calibration script) would half-parse.

#include "io/atomic_file.hpp"

namespace demcal::dem {

using io::write_file_atomically;

}  // namespace demcal::dem

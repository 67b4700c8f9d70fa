#pragma once
// The canonical text of a JSON value (object keys sorted, no whitespace, an
// integral double below 2^53 written as that integer, other numbers in their
// shortest round-trip text) and SHA-256 over text: what run keys, record
// digests and stage digests are made of (study/run_store.hpp states the rule).

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace demcal::config {

// SHA-256 as 64 lowercase hex digits.
std::string sha256_hex(std::string_view data);

// The canonical text of `j` (see the hash rule above).
std::string canonical_json(const nlohmann::json& j);

}  // namespace demcal::config

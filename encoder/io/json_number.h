// Whole numbers read from JSON with their range checked. nlohmann's get<int>()
// converts whatever number it finds, and a float beyond the type's range is
// undefined behaviour (found by fuzz_prepared); files users bring go through
// this instead.
#ifndef FVV_ENCODER_IO_JSON_NUMBER_H_
#define FVV_ENCODER_IO_JSON_NUMBER_H_

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace fvv {

// `j` as a T when it is a whole number (written without a fraction or
// exponent) in T's range; otherwise std::out_of_range naming `what`, which
// the parsers' catch of nlohmann's exceptions turns into Corrupt.
template <typename T>
T JsonWhole(const nlohmann::json& j, const std::string& what) {
  static_assert(std::is_integral_v<T>, "whole numbers only");
  const auto fail = [&] {
    return std::out_of_range(what + " is not a whole number in " +
                             std::to_string(std::numeric_limits<T>::min()) + ".." +
                             std::to_string(std::numeric_limits<T>::max()));
  };
  if (j.is_number_unsigned()) {
    const uint64_t v = j.get<uint64_t>();
    if (v > uint64_t(std::numeric_limits<T>::max())) throw fail();
    return T(v);
  }
  if (j.is_number_integer()) {
    const int64_t v = j.get<int64_t>();
    if (v < int64_t(std::numeric_limits<T>::min()) ||
        (v > 0 && uint64_t(v) > uint64_t(std::numeric_limits<T>::max()))) {
      throw fail();
    }
    return T(v);
  }
  throw fail();
}

}  // namespace fvv

#endif  // FVV_ENCODER_IO_JSON_NUMBER_H_

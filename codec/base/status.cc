#include "codec/base/status.h"

#include "fvv/fvv_types.h"

namespace fvv {

const char* StatusCodeName(StatusCode code) {
  switch (code) {
    case StatusCode::kOk:
      return "ok";
    case StatusCode::kInvalidArgument:
      return "invalid argument";
    case StatusCode::kTruncated:
      return "truncated";
    case StatusCode::kCorrupt:
      return "corrupt";
    case StatusCode::kLimitExceeded:
      return "limit exceeded";
    case StatusCode::kUnsupported:
      return "unsupported";
    case StatusCode::kChecksumMismatch:
      return "checksum mismatch";
    case StatusCode::kIoError:
      return "i/o error";
    case StatusCode::kOutOfMemory:
      return "out of memory";
    case StatusCode::kInternal:
      return "internal error";
  }
  return "unknown";
}

std::string Status::ToString() const {
  if (ok()) return "ok";
  return std::string(StatusCodeName(code_)) + ": " + message_;
}

}  // namespace fvv

// The public codes are the internal ones, number for number.
static_assert(FVV_OK == static_cast<int>(fvv::StatusCode::kOk) &&
                  FVV_INVALID_ARGUMENT == static_cast<int>(fvv::StatusCode::kInvalidArgument) &&
                  FVV_TRUNCATED == static_cast<int>(fvv::StatusCode::kTruncated) &&
                  FVV_CORRUPT == static_cast<int>(fvv::StatusCode::kCorrupt) &&
                  FVV_LIMIT_EXCEEDED == static_cast<int>(fvv::StatusCode::kLimitExceeded) &&
                  FVV_UNSUPPORTED == static_cast<int>(fvv::StatusCode::kUnsupported) &&
                  FVV_CHECKSUM_MISMATCH == static_cast<int>(fvv::StatusCode::kChecksumMismatch) &&
                  FVV_IO_ERROR == static_cast<int>(fvv::StatusCode::kIoError) &&
                  FVV_OUT_OF_MEMORY == static_cast<int>(fvv::StatusCode::kOutOfMemory) &&
                  FVV_INTERNAL == static_cast<int>(fvv::StatusCode::kInternal),
              "fvv_status and StatusCode are pinned to the same numbers");

extern "C" const char* fvv_status_name(fvv_status status) {
  return fvv::StatusCodeName(static_cast<fvv::StatusCode>(status));
}

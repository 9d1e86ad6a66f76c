// Status and StatusOr: how every internal fvv function reports failure.
// A Status carries a pinned code (the same numbers as the public fvv_status in
// include/fvv/fvv_types.h) and a message that says what failed and where.
#ifndef FVV_CODEC_BASE_STATUS_H_
#define FVV_CODEC_BASE_STATUS_H_

#include <string>
#include <utility>
#include <variant>

namespace fvv {

// Pinned: these values are part of the public C API and never change.
enum class StatusCode : int {
  kOk = 0,
  kInvalidArgument = 1,   // caller passed something unusable
  kTruncated = 2,         // input ended before a syntax element was complete
  kCorrupt = 3,           // input violates the bitstream syntax
  kLimitExceeded = 4,     // a count or size is beyond the profile/level limits
  kUnsupported = 5,       // valid syntax this decoder does not implement (e.g. newer version)
  kChecksumMismatch = 6,  // integrity check failed
  kIoError = 7,           // file system or external program failure
  kOutOfMemory = 8,
  kInternal = 9,  // a bug in fvv
};

const char* StatusCodeName(StatusCode code);

class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status Ok() { return Status(); }
  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  // "corrupt: SPIHT stream of channel U: bitplane count 40 exceeds 30"
  std::string ToString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

inline Status InvalidArgument(std::string m) {
  return {StatusCode::kInvalidArgument, std::move(m)};
}
inline Status Truncated(std::string m) { return {StatusCode::kTruncated, std::move(m)}; }
inline Status Corrupt(std::string m) { return {StatusCode::kCorrupt, std::move(m)}; }
inline Status LimitExceeded(std::string m) { return {StatusCode::kLimitExceeded, std::move(m)}; }
inline Status Unsupported(std::string m) { return {StatusCode::kUnsupported, std::move(m)}; }
inline Status IoError(std::string m) { return {StatusCode::kIoError, std::move(m)}; }
inline Status Internal(std::string m) { return {StatusCode::kInternal, std::move(m)}; }

template <typename T>
class [[nodiscard]] StatusOr {
 public:
  StatusOr(T value) : v_(std::move(value)) {}  // NOLINT: implicit by design, like absl
  StatusOr(Status status) : v_(std::move(status)) {
    if (std::get<Status>(v_).ok()) v_ = Status(StatusCode::kInternal, "StatusOr from OK status");
  }
  bool ok() const { return std::holds_alternative<T>(v_); }
  const Status& status() const {
    static const Status kOk;
    return ok() ? kOk : std::get<Status>(v_);
  }
  T& value() & { return std::get<T>(v_); }
  const T& value() const& { return std::get<T>(v_); }
  T&& value() && { return std::get<T>(std::move(v_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  std::variant<Status, T> v_;
};

}  // namespace fvv

#define FVV_STATUS_CONCAT_INNER(a, b) a##b
#define FVV_STATUS_CONCAT(a, b) FVV_STATUS_CONCAT_INNER(a, b)

#define FVV_RETURN_IF_ERROR(expr)              \
  do {                                         \
    ::fvv::Status fvv_status_ = (expr);        \
    if (!fvv_status_.ok()) return fvv_status_; \
  } while (0)

// FVV_ASSIGN_OR_RETURN(auto x, Foo()); declares x from a StatusOr or returns its error.
#define FVV_ASSIGN_OR_RETURN(lhs, expr)                         \
  auto FVV_STATUS_CONCAT(fvv_statusor_, __LINE__) = (expr);     \
  if (!FVV_STATUS_CONCAT(fvv_statusor_, __LINE__).ok())         \
    return FVV_STATUS_CONCAT(fvv_statusor_, __LINE__).status(); \
  lhs = std::move(FVV_STATUS_CONCAT(fvv_statusor_, __LINE__)).value()

#endif  // FVV_CODEC_BASE_STATUS_H_

// A stream known by the byte ranges fetched of it so far (HTTP range requests
// from a web page): the random-access reader reads through it, and a read of
// bytes not yet fetched fails and says which range to fetch.
#ifndef FVV_CONTAINER_FETCHED_SOURCE_H_
#define FVV_CONTAINER_FETCHED_SOURCE_H_

#include <cstdint>
#include <map>
#include <vector>

#include "container/file_reader.h"

namespace fvv {

class FetchedSource : public ByteSource {
 public:
  // `size`: the whole stream's bytes (a server's Content-Range says it).
  explicit FetchedSource(uint64_t size) : size_(size) {}

  uint64_t size() const override { return size_; }
  // Truncated, and `missing` set, when any of the bytes has not been fetched.
  Status Read(uint64_t offset, size_t n, uint8_t* out) override;

  // Bytes at `offset`; they join the ranges they touch. Bytes already held are
  // kept (a refetch of the same range brings the same bytes).
  Status Add(uint64_t offset, const uint8_t* data, size_t n);
  // How many bytes from `offset` on are held without a gap.
  uint64_t HeldFrom(uint64_t offset) const;
  uint64_t held_bytes() const { return held_; }

  // The bytes a failed Read lacked (from its first byte not held), since the
  // last Add; false when none did.
  bool missing(uint64_t* offset, uint64_t* n) const;

 private:
  uint64_t size_;
  uint64_t held_ = 0;
  std::map<uint64_t, std::vector<uint8_t>> ranges_;  // by first byte; disjoint, not adjacent
  bool missing_ = false;
  uint64_t missing_offset_ = 0, missing_size_ = 0;
};

}  // namespace fvv

#endif  // FVV_CONTAINER_FETCHED_SOURCE_H_

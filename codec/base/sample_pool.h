// Recycles the large sample buffers of decoded blocks between decodes. A player
// decodes GOP after GOP of the same shape; handing the previous GOP's buffers to
// the next one saves the page faults and kernel zeroing of fresh allocations
// (about a tenth of a full decode's time otherwise).
#ifndef FVV_CODEC_BASE_SAMPLE_POOL_H_
#define FVV_CODEC_BASE_SAMPLE_POOL_H_

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

namespace fvv {

class SamplePool {
 public:
  // An empty buffer, with the capacity of a returned one when there is one.
  std::vector<int32_t> Take() {
    std::lock_guard<std::mutex> lock(mu_);
    if (free_.empty()) return {};
    std::vector<int32_t> buffer = std::move(free_.back());
    free_.pop_back();
    buffer.clear();
    return buffer;
  }
  // Keeps `buffer` for a later Take, up to the limit (the rest is freed).
  void Give(std::vector<int32_t> buffer) {
    std::lock_guard<std::mutex> lock(mu_);
    if (buffer.capacity() > 0 && free_.size() < max_buffers_) free_.push_back(std::move(buffer));
  }
  // At most this many buffers are kept (default 0: none); lowering it frees the excess.
  void SetLimit(size_t max_buffers) {
    std::lock_guard<std::mutex> lock(mu_);
    max_buffers_ = max_buffers;
    if (free_.size() > max_buffers_) free_.resize(max_buffers_);
  }
  size_t pooled() const {
    std::lock_guard<std::mutex> lock(mu_);
    return free_.size();
  }

 private:
  mutable std::mutex mu_;
  size_t max_buffers_ = 0;
  std::vector<std::vector<int32_t>> free_;
};

}  // namespace fvv

#endif  // FVV_CODEC_BASE_SAMPLE_POOL_H_

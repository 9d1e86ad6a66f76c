#include "container/fetched_source.h"

#include <algorithm>
#include <cstring>

namespace fvv {

Status FetchedSource::Read(uint64_t offset, size_t n, uint8_t* out) {
  if (offset > size_ || n > size_ - offset) return Internal("read past the end of the stream");
  if (n == 0) return Status::Ok();
  auto it = ranges_.upper_bound(offset);
  if (it != ranges_.begin()) {
    --it;
    if (offset + n <= it->first + it->second.size()) {
      std::memcpy(out, it->second.data() + (offset - it->first), n);
      return Status::Ok();
    }
  }
  // From the first byte not held: a client that fetched part of it goes on.
  const uint64_t held = HeldFrom(offset);
  missing_ = true;
  missing_offset_ = offset + held;
  missing_size_ = n - held;
  return Truncated("bytes " + std::to_string(offset) + " to " + std::to_string(offset + n) +
                   " have not been fetched");
}

Status FetchedSource::Add(uint64_t offset, const uint8_t* data, size_t n) {
  if (offset > size_ || n > size_ - offset) {
    return InvalidArgument("bytes " + std::to_string(offset) + " to " + std::to_string(offset + n) +
                           " lie past the stream's " + std::to_string(size_) + " bytes");
  }
  missing_ = false;
  if (n == 0) return Status::Ok();
  uint64_t first = offset, end = offset + n;
  // The ranges the new bytes overlap or touch.
  auto it = ranges_.upper_bound(first);
  if (it != ranges_.begin() && std::prev(it)->first + std::prev(it)->second.size() >= first) --it;
  std::vector<std::map<uint64_t, std::vector<uint8_t>>::iterator> absorbed;
  for (; it != ranges_.end() && it->first <= end; ++it) absorbed.push_back(it);
  if (absorbed.size() == 1 && absorbed[0]->first <= first) {
    // The common case (a fragment or the head fetched piece by piece): a
    // range grows at its end, without copying what it holds.
    std::vector<uint8_t>& held = absorbed[0]->second;
    const uint64_t held_end = absorbed[0]->first + held.size();
    if (end > held_end) {
      held.insert(held.end(), data + static_cast<size_t>(held_end - offset), data + n);
      held_ += end - held_end;
    }
    return Status::Ok();
  }
  if (!absorbed.empty()) {
    first = std::min(first, absorbed.front()->first);
    end = std::max(end, absorbed.back()->first + absorbed.back()->second.size());
  }
  std::vector<uint8_t> merged(static_cast<size_t>(end - first));
  std::memcpy(merged.data() + (offset - first), data, n);
  for (auto& a : absorbed) {  // bytes held win: they were there first
    std::memcpy(merged.data() + (a->first - first), a->second.data(), a->second.size());
    held_ -= a->second.size();
    ranges_.erase(a);
  }
  held_ += merged.size();
  ranges_.emplace(first, std::move(merged));
  return Status::Ok();
}

uint64_t FetchedSource::HeldFrom(uint64_t offset) const {
  auto it = ranges_.upper_bound(offset);
  if (it == ranges_.begin()) return 0;
  --it;
  const uint64_t end = it->first + it->second.size();
  return end > offset ? end - offset : 0;
}

bool FetchedSource::missing(uint64_t* offset, uint64_t* n) const {
  if (!missing_) return false;
  *offset = missing_offset_;
  *n = missing_size_;
  return true;
}

}  // namespace fvv

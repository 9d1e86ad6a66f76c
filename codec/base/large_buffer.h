// Sizing of the codec's large sample and coefficient buffers (tens of MiB per
// channel of a GOP). Fresh memory of that size arrives untouched from the
// kernel, and its first write faults in one 4 KiB page at a time: on the
// virtual machines we measure on, that was more than half of a first GOP
// decode. Where the kernel offers transparent huge pages
// on request (Linux, THP mode "madvise" or "always"), asking for them before
// the first write cuts the faults 512-fold. Elsewhere, or where the request is
// refused, the buffer is the same, only slower to fault in.
#ifndef FVV_CODEC_BASE_LARGE_BUFFER_H_
#define FVV_CODEC_BASE_LARGE_BUFFER_H_

#include <cstddef>
#include <vector>

namespace fvv {

// Asks the kernel to back [data, data + bytes) with huge pages where it can
// (whole 2 MiB pages inside the range only; small ranges are left alone).
// Advice only: never fails, never changes the contents.
void AdviseHugePages(void* data, size_t bytes);

// v->assign(n, value), where a buffer that must grow is reserved and advised
// before the first write.
template <typename T>
void AssignLarge(std::vector<T>* v, size_t n, const T& value = T{}) {
  if (v->capacity() < n) {
    std::vector<T> fresh;
    fresh.reserve(n);
    AdviseHugePages(fresh.data(), n * sizeof(T));
    *v = std::move(fresh);
  }
  v->assign(n, value);
}

}  // namespace fvv

#endif  // FVV_CODEC_BASE_LARGE_BUFFER_H_

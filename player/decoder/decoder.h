// The decoder behind the C API (include/fvv/fvv_decoder.h): input by file
// (random access through the index), by byte ranges fetched piecemeal (random
// access over what has arrived) or by pushed bytes (streaming), a cache of the
// last decoded GOP, and decode-ahead of the next one on a worker thread.
#ifndef FVV_PLAYER_DECODER_DECODER_H_
#define FVV_PLAYER_DECODER_DECODER_H_

#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "codec/base/sample_pool.h"
#include "codec/base/thread_pool.h"
#include "container/fetched_source.h"
#include "container/file_reader.h"
#include "container/stream_reader.h"
#include "fvv/fvv_decoder.h"
#include "player/decoder/gop_decoder.h"

namespace fvv {

class Decoder {
 public:
  explicit Decoder(const fvv_decoder_settings& settings);
  ~Decoder();

  Status OpenFile(const std::string& path);
  // Byte ranges: the stream's size, then its bytes as they arrive (any order).
  Status OpenRanges(uint64_t stream_size);
  Status AddRange(uint64_t offset, const uint8_t* data, size_t size);
  // The range the header boxes or index still need (false: none).
  bool WantedRange(uint64_t* offset, uint64_t* size) const;
  // Bytes of `fragment` held from its first on (ranges input; all of it otherwise).
  uint64_t FragmentBytesHeld(size_t fragment) const;
  // The bytes past `fragment`'s head that carry its surface whole
  // (SurfaceChunkBytes), once the decoder has read its head; 0 before, and
  // without a surface.
  uint64_t FragmentSurfaceBytes(size_t fragment) const;
  bool random_access() const { return file_ != nullptr; }
  Status Push(const uint8_t* data, size_t size);
  Status PushEnd();
  StatusOr<fvv_event> Process();

  bool ready() const { return ready_; }
  const StreamInfo& info() const;
  uint32_t frames_available() const { return frames_available_; }

  // The decoded GOP holding `frame`, decoded at least as well as `budget` asks.
  StatusOr<std::shared_ptr<const DecodedGop>> Gop(uint32_t frame, const GopBudget& budget);
  // Starts decoding the GOP holding `frame` in the background (if it is neither
  // cached nor already being decoded); Ready says whether Gop would return at once.
  Status Prefetch(uint32_t frame, const GopBudget& budget);
  bool Ready(uint32_t frame, const GopBudget& budget);

 private:
  // The span's fragments, camera group 0 first. With ranges input, the
  // groups `budget` leaves out are their grid cells only (nothing fetched).
  Status SpanFragments(uint32_t span, const GopBudget& budget, std::vector<FragmentData>* out);
  StatusOr<std::shared_ptr<DecodedGop>> DecodeSpan(uint32_t span, const GopBudget& budget);
  // The budget with its camera mask widened to whole camera groups (0 when
  // that is every camera), so that masks compare by what a decode holds.
  GopBudget Normalised(GopBudget budget) const;
  // Whether a GOP decoded under `cached` is what a request under `wanted` gets.
  static bool SameBudget(const GopBudget& cached, const GopBudget& wanted);
  // Decodes `span` in the background; `requested`: asked for by the caller
  // (Prefetch), not the automatic decode-ahead that settings can turn off.
  void StartBackgroundDecode(uint32_t span, const GopBudget& budget, bool requested);
  void WaitDecodeAhead();
  uint32_t span_count() const;
  // The readers' options: the settings' claim (SPEC.md 5.1).
  FragmentReadOptions ReadOptions() const;

  fvv_decoder_settings settings_;
  ThreadPool pool_;
  // Texture buffers of dropped GOPs, for the next decode (one span's worth).
  std::shared_ptr<SamplePool> samples_ = std::make_shared<SamplePool>();
  bool ready_ = false, ready_reported_ = false, end_reported_ = false;
  uint32_t frames_available_ = 0, frames_reported_ = 0;

  // Random access: a file, or the ranges fetched of a stream.
  std::unique_ptr<ByteSource> source_;
  FetchedSource* fetched_ = nullptr;  // source_, with ranges input
  std::unique_ptr<FileReader> file_;
  // Streaming.
  std::unique_ptr<StreamReader> stream_;
  bool stream_ended_ = false;
  std::map<uint32_t, FragmentData> buffered_;  // by GOP index
  uint64_t buffered_bytes_ = 0;

  std::shared_ptr<const DecodedGop> cache_;
  // A GOP decoded ahead that a prefetch of another span displaced once it was
  // done (a looping player asks for the first GOP while the last one waits):
  // kept until it is asked for or another one is parked.
  std::shared_ptr<const DecodedGop> parked_;
  std::future<StatusOr<std::shared_ptr<DecodedGop>>> ahead_;
  uint32_t ahead_span_ = 0;
  GopBudget ahead_budget_;
  // FragmentSurfaceBytes, by fragment index, as each was read (decoding
  // ahead reads on another thread).
  mutable std::mutex surface_bytes_mutex_;
  std::map<uint32_t, uint64_t> surface_bytes_;
};

}  // namespace fvv

#endif  // FVV_PLAYER_DECODER_DECODER_H_

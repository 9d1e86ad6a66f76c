#include "player/decoder/decoder.h"

#include "codec/base/threads.h"

namespace fvv {
namespace {

constexpr uint64_t kDefaultMemoryCap = uint64_t{1} << 30;

uint64_t FragmentBytes(const FragmentData& f) {
  return TextureBytes(f) + f.motion.size() + f.masks.size() + f.vertex_visibility.size();
}

}  // namespace

Decoder::Decoder(const fvv_decoder_settings& settings)
    : settings_(settings), pool_(settings.threads) {
  if (settings_.memory_cap_bytes == 0) settings_.memory_cap_bytes = kDefaultMemoryCap;
}

Decoder::~Decoder() { WaitDecodeAhead(); }

const StreamInfo& Decoder::info() const { return file_ ? file_->info() : stream_->info(); }

FragmentReadOptions Decoder::ReadOptions() const {
  FragmentReadOptions o;
  o.max_fragment_bytes = settings_.max_fragment_bytes;
  o.max_gop_samples = settings_.max_gop_samples;
  return o;
}

uint32_t Decoder::span_count() const {
  const FileHeader& h = info().header;
  // A live stream's spans are those of the frames that have arrived.
  return h.frame_count != 0 ? h.time_spans()
                            : (frames_available_ + h.gop_frames - 1) / h.gop_frames;
}

Status Decoder::OpenFile(const std::string& path) {
  if (source_ || stream_) return InvalidArgument("the decoder already has an input");
  FVV_ASSIGN_OR_RETURN(std::unique_ptr<FileSource> file, FileSource::Open(path));
  source_ = std::move(file);
  auto reader = FileReader::Open(source_.get(), ReadOptions());
  if (!reader.ok()) {
    source_.reset();
    return Status(reader.status().code(), path + ": " + reader.status().message());
  }
  file_ = std::move(reader).value();
  ready_ = true;
  frames_available_ = file_->info().frames();
  return Status::Ok();
}

Status Decoder::OpenRanges(uint64_t stream_size) {
  if (source_ || stream_) return InvalidArgument("the decoder already has an input");
  if (stream_size == 0) return InvalidArgument("a stream of 0 bytes");
  auto fetched = std::make_unique<FetchedSource>(stream_size);
  fetched_ = fetched.get();
  source_ = std::move(fetched);
  // The player decides what to fetch and decode next: nothing decodes ahead
  // on bytes that may still grow.
  settings_.decode_ahead = 0;
  return Status::Ok();
}

Status Decoder::AddRange(uint64_t offset, const uint8_t* data, size_t size) {
  if (!fetched_) return InvalidArgument("add_range without open_ranges");
  FVV_RETURN_IF_ERROR(fetched_->Add(offset, data, size));
  if (!file_) return Status::Ok();
  // A GOP decoded from fewer bytes of a fragment these reach is decoded again.
  const uint64_t end = offset + size;
  const auto touched = [&](uint32_t span) {
    const uint32_t groups = info().header.camera_groups();
    for (uint32_t g = 0; g < groups; ++g) {
      const IndexEntry& e = info().index[size_t{span} * groups + g];
      if (offset < e.offset + e.size && end > e.offset) return true;
    }
    return false;
  };
  // A prefetch under way of a span these bytes reach decodes from fewer:
  // its result is dropped (the others' wait for their callers).
  if (ahead_.valid() && touched(ahead_span_)) {
    auto stale = ahead_.get();
    (void)stale;
  }
  if (cache_ && touched(cache_->span)) cache_.reset();
  if (parked_ && touched(parked_->span)) parked_.reset();
  return Status::Ok();
}

bool Decoder::WantedRange(uint64_t* offset, uint64_t* size) const {
  if (!fetched_ || file_) return false;
  if (!fetched_->missing(offset, size)) return false;
  // The header boxes are read one box at a time: the box asked for and 4 KiB
  // more, for the next boxes' headers (and the small ones whole), saves most
  // requests without running on into the fragments, which the player fetches
  // as prefixes.
  *size = std::min(fetched_->size() - *offset, *size + (uint64_t{4} << 10));
  return true;
}

uint64_t Decoder::FragmentBytesHeld(size_t fragment) const {
  const IndexEntry& e = info().index[fragment];
  return fetched_ ? std::min(e.size, fetched_->HeldFrom(e.offset)) : e.size;
}

uint64_t Decoder::FragmentSurfaceBytes(size_t fragment) const {
  std::lock_guard<std::mutex> lock(surface_bytes_mutex_);
  const auto it = surface_bytes_.find(uint32_t(fragment));
  return it == surface_bytes_.end() ? 0 : it->second;
}

Status Decoder::Push(const uint8_t* data, size_t size) {
  if (source_)
    return InvalidArgument("push after open_file or open_ranges: a decoder has one input");
  if (stream_ended_) return InvalidArgument("push after push_end");
  if (!stream_) stream_ = std::make_unique<StreamReader>(ReadOptions());
  if (size > 0) stream_->Push(data, size);
  return Status::Ok();
}

Status Decoder::PushEnd() {
  if (source_) return InvalidArgument("push_end after open_file or open_ranges");
  if (!stream_) stream_ = std::make_unique<StreamReader>(ReadOptions());
  stream_->Finish();
  stream_ended_ = true;
  return Status::Ok();
}

StatusOr<fvv_event> Decoder::Process() {
  if (fetched_ && !file_) {
    // The header boxes and the index, as far as the ranges fetched reach.
    auto reader = FileReader::Open(fetched_, ReadOptions(), /*require_index=*/true);
    uint64_t offset, size;
    if (!reader.ok() && fetched_->missing(&offset, &size)) return FVV_EVENT_NEED_MORE_INPUT;
    FVV_RETURN_IF_ERROR(reader.status());
    file_ = std::move(reader).value();
    ready_ = true;
    frames_available_ = file_->info().frames();
  }
  if (!file_ && !stream_) return FVV_EVENT_NEED_MORE_INPUT;  // streaming starts empty
  if (file_) {
    if (!ready_reported_) {
      ready_reported_ = true;
      return FVV_EVENT_READY;
    }
    if (frames_reported_ < frames_available_) {
      frames_reported_ = frames_available_;
      return FVV_EVENT_FRAMES;
    }
    end_reported_ = true;
    return FVV_EVENT_END;
  }
  for (;;) {
    if (ready_ && !ready_reported_) {
      ready_reported_ = true;
      return FVV_EVENT_READY;
    }
    if (frames_reported_ < frames_available_) {
      frames_reported_ = frames_available_;
      return FVV_EVENT_FRAMES;
    }
    FVV_ASSIGN_OR_RETURN(const ReaderEvent e, stream_->Next());
    const StreamInfo& si = stream_->info();
    switch (e) {
      case ReaderEvent::kNeedMoreInput:
        return FVV_EVENT_NEED_MORE_INPUT;
      case ReaderEvent::kEnd:
        end_reported_ = true;
        return FVV_EVENT_END;
      case ReaderEvent::kFragment: {
        FragmentData f = stream_->TakeFragment();
        const uint32_t groups = si.header.camera_groups();
        const bool span_done = f.info.first_camera / si.header.gop_cameras == groups - 1;
        const uint32_t end_frame = f.info.first_frame + f.info.frame_count;
        buffered_bytes_ += FragmentBytes(f);
        buffered_.emplace(f.info.gop_index, std::move(f));
        // Bounded memory: the oldest spans go first (they can no longer be decoded).
        while (buffered_bytes_ > settings_.memory_cap_bytes && buffered_.size() > groups) {
          buffered_bytes_ -= FragmentBytes(buffered_.begin()->second);
          buffered_.erase(buffered_.begin());
        }
        if (span_done) frames_available_ = end_frame;
        break;
      }
      default:
        ready_ = si.has_header && si.has_cameras && si.has_model && si.has_motion;
        break;
    }
  }
}

Status Decoder::SpanFragments(uint32_t span, const GopBudget& budget,
                              std::vector<FragmentData>* out) {
  const FileHeader& h = info().header;
  const uint32_t groups = h.camera_groups();
  out->clear();
  for (uint32_t g = 0; g < groups; ++g) {
    const uint32_t index = span * groups + g;
    if (fetched_) {
      const IndexEntry& e = info().index[index];
      if (g > 0 && !budget.WantsGroup(e.first_camera, e.camera_count)) {
        FragmentData cell;  // not decoded: its grid cell is all DecodeGop reads
        cell.info = {index, e.first_frame, e.frame_count, e.first_camera, e.camera_count};
        out->push_back(std::move(cell));
        continue;
      }
      const uint64_t held = FragmentBytesHeld(index);
      if (held == 0) {
        return InvalidArgument("fragment " + std::to_string(index) + " (bytes " +
                               std::to_string(e.offset) + " to " +
                               std::to_string(e.offset + e.size) + ") has not been fetched");
      }
      FVV_ASSIGN_OR_RETURN(FragmentData f, file_->ReadFragment(index, held));
      {
        std::lock_guard<std::mutex> lock(surface_bytes_mutex_);
        surface_bytes_[index] = SurfaceChunkBytes(f);
      }
      out->push_back(std::move(f));
    } else if (file_) {
      FVV_ASSIGN_OR_RETURN(FragmentData f, file_->ReadFragment(index));
      {
        std::lock_guard<std::mutex> lock(surface_bytes_mutex_);
        surface_bytes_[index] = SurfaceChunkBytes(f);
      }
      out->push_back(std::move(f));
    } else {
      auto it = buffered_.find(index);
      if (it == buffered_.end()) {
        return InvalidArgument("GOP " + std::to_string(index) +
                               " is no longer buffered (memory cap) or has not arrived");
      }
      out->push_back(it->second);
    }
  }
  return Status::Ok();
}

StatusOr<std::shared_ptr<DecodedGop>> Decoder::DecodeSpan(uint32_t span, const GopBudget& budget) {
  std::vector<FragmentData> fragments;
  FVV_RETURN_IF_ERROR(SpanFragments(span, budget, &fragments));
  samples_->SetLimit(3 * fragments.size());
  return DecodeGop(info(), fragments, budget, pool_.runner(), pool_.size(), samples_);
}

void Decoder::StartBackgroundDecode(uint32_t span, const GopBudget& budget, bool requested) {
  if ((!requested && !settings_.decode_ahead) || ahead_.valid() || span >= span_count()) return;
  if (!file_ && (span + 1) * info().header.gop_frames > frames_available_ &&
      (span + 1) * info().header.gop_frames < info().header.frame_count) {
    return;  // not all of it has arrived
  }
  std::vector<FragmentData> fragments;
  if (!SpanFragments(span, budget, &fragments).ok()) return;  // reported when asked for
  if (!kThreadsAvailable) {
    // No background: a prefetch asked for decodes now, and its GOP waits parked.
    if (!requested) return;
    auto done = DecodeGop(info(), fragments, budget, pool_.runner(), pool_.size(), samples_);
    if (done.ok()) parked_ = std::move(done).value();
    return;
  }
  ahead_span_ = span;
  ahead_budget_ = budget;
  const StreamInfo* si = &info();
  ThreadPool* pool = &pool_;
  samples_->SetLimit(3 * fragments.size());
  ahead_ = std::async(
      std::launch::async, [si, pool, budget, samples = samples_, fragments = std::move(fragments)] {
        return DecodeGop(*si, fragments, budget, pool->runner(), pool->size(), samples);
      });
}

void Decoder::WaitDecodeAhead() {
  if (ahead_.valid()) ahead_.wait();
}

// Budgets match when equal, or when both are time budgets: a player in
// real-time mode retunes its time budget every GOP and picks the cameras from a
// view that moves, and a GOP decoded ahead under the previous budget and camera
// set is what it wants (decoding it again would cost the very time the budget
// protects; the GOP after it is decoded with the new set).
bool Decoder::SameBudget(const GopBudget& cached, const GopBudget& wanted) {
  if (cached.max_ms > 0 && wanted.max_ms > 0) return true;
  // A GOP holding more cameras than asked for serves the request: a player's
  // view-dependent camera set changes with the view, and a superset decoded
  // ahead must not be decoded again.
  const bool cameras =
      cached.cameras == 0 || (wanted.cameras != 0 && (wanted.cameras & ~cached.cameras) == 0);
  GopBudget a = cached, b = wanted;
  a.cameras = b.cameras = 0;
  return cameras && a.Covers(b) && b.Covers(a);
}

GopBudget Decoder::Normalised(GopBudget b) const {
  if (b.cameras == 0) return b;
  // Camera groups decode whole: ask for every camera of each group asked for.
  const FileHeader& h = info().header;
  uint64_t mask = 0;
  for (uint32_t first = 0; first < h.camera_count && first < 64; first += h.gop_cameras) {
    const uint32_t count = std::min<uint32_t>(h.gop_cameras, h.camera_count - first);
    if (!b.WantsGroup(first, count)) continue;
    for (uint32_t c = first; c < first + count && c < 64; ++c) mask |= uint64_t{1} << c;
  }
  const bool all =
      h.camera_count <= 64 &&
      mask == (h.camera_count == 64 ? ~uint64_t{0} : (uint64_t{1} << h.camera_count) - 1);
  b.cameras = all ? 0 : mask;
  return b;
}

Status Decoder::Prefetch(uint32_t frame, const GopBudget& asked) {
  const GopBudget budget = ready_ ? Normalised(asked) : asked;
  if (!ready_) return InvalidArgument("prefetch before the stream's header boxes were read");
  if (frame >= frames_available_) return InvalidArgument("prefetch of an unavailable frame");
  const uint32_t span = frame / info().header.gop_frames;
  if (cache_ && cache_->span == span && SameBudget(cache_->budget, budget)) return Status::Ok();
  if (ahead_.valid()) {
    // Already under way with a budget that serves this request.
    if (ahead_span_ == span && SameBudget(ahead_budget_, budget)) return Status::Ok();
    if (ahead_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      return Status::Ok();  // one background decode at a time; ask again later
    }
    auto done = ahead_.get();
    if (done.ok()) parked_ = std::move(done).value();
  }
  if (parked_ && parked_->span == span && SameBudget(parked_->budget, budget)) {
    return Status::Ok();
  }
  StartBackgroundDecode(span, budget, /*requested=*/true);
  return Status::Ok();
}

bool Decoder::Ready(uint32_t frame, const GopBudget& asked) {
  if (!ready_ || frame >= frames_available_) return false;
  const GopBudget budget = Normalised(asked);
  const uint32_t span = frame / info().header.gop_frames;
  if (cache_ && cache_->span == span && SameBudget(cache_->budget, budget)) return true;
  if (parked_ && parked_->span == span && SameBudget(parked_->budget, budget)) return true;
  return ahead_.valid() && ahead_span_ == span && SameBudget(ahead_budget_, budget) &&
         ahead_.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

StatusOr<std::shared_ptr<const DecodedGop>> Decoder::Gop(uint32_t frame, const GopBudget& asked) {
  if (!ready_) return InvalidArgument("decode before the stream's header boxes were read");
  const GopBudget budget = Normalised(asked);
  if (frame >= frames_available_) {
    return InvalidArgument("frame " + std::to_string(frame) + " is not available (" +
                           std::to_string(frames_available_) + " frames decodable)");
  }
  const uint32_t span = frame / info().header.gop_frames;
  if (cache_ && cache_->span == span && SameBudget(cache_->budget, budget)) return cache_;
  if (parked_ && parked_->span == span && SameBudget(parked_->budget, budget)) {
    // The decode under way (if any) is for a later span: it goes on.
    cache_ = std::move(parked_);
    StartBackgroundDecode(span + 1, budget, /*requested=*/false);
    return cache_;
  }
  std::shared_ptr<DecodedGop> gop;
  if (ahead_.valid() && ahead_span_ == span && SameBudget(ahead_budget_, budget)) {
    auto result = ahead_.get();
    if (result.ok()) gop = std::move(result).value();
  } else if (ahead_.valid()) {
    auto dropped = ahead_.get();  // a different span or budget: its work is not used
    (void)dropped;
  }
  if (!gop) {
    FVV_ASSIGN_OR_RETURN(gop, DecodeSpan(span, budget));
  }
  cache_ = gop;
  StartBackgroundDecode(span + 1, budget, /*requested=*/false);
  return cache_;
}

}  // namespace fvv

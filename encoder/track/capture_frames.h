// Per-frame camera images and silhouettes of a capture, for every camera at
// once (both cores): the given silhouettes; or the person a pretrained network
// sees (its mask, refined along its edge by background subtraction when there are
// plates); or background subtraction against the plates (or the temporal
// median of frames spread over the take when a camera has none). What tracking
// and the encoder's texture resampling read.
#ifndef FVV_ENCODER_TRACK_CAPTURE_FRAMES_H_
#define FVV_ENCODER_TRACK_CAPTURE_FRAMES_H_

#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "codec/base/thread_pool.h"
#include "encoder/capture/capture.h"
#include "encoder/track/person_observer.h"
#include "encoder/track/silhouette.h"

namespace fvv {

class CaptureFrames {
 public:
  // `extract`: background subtraction even when the capture lists silhouettes.
  // `persons`: silhouettes from the person network instead of (without plates)
  // or together with (with plates) background subtraction; not owned.
  static StatusOr<std::unique_ptr<CaptureFrames>> Open(const Capture& capture, bool extract,
                                                       ThreadPool* pool,
                                                       PersonObserver* persons = nullptr);

  bool given_silhouettes() const { return given_; }
  // The silhouettes are the person network's masks (alone or with background
  // subtraction): their outlines are coarser than given or subtracted ones.
  bool person_masks() const { return !given_ && persons_ != nullptr; }
  // "given", "person masks", "person masks and background subtraction" or
  // "background subtraction".
  std::string silhouette_source() const;
  const Capture& capture() const { return reader_.capture(); }

  // Frame `frame` of every camera: silhouettes (grey, 0 or 255) and, when
  // `images` is not null, the RGB images.
  Status Read(uint32_t frame, std::vector<Image>* images, std::vector<Image>* silhouettes);
  // The body joints the person network saw in the frame Read last, per
  // camera (empty without the network), with left and right exchanged in a
  // camera that named them the other way round (ExchangeMislabelledSides).
  const std::vector<std::vector<JointSighting>>& sightings() const { return sightings_; }
  // Camera frames so far whose sightings had their sides exchanged.
  uint32_t side_exchanges() const { return side_exchanges_; }
  // Starts decoding `frame`'s images on a thread of its own, for the Read of
  // it that comes next: with the person network, decoding large frames costs
  // half of what the network does and would otherwise wait for it. Only
  // between Reads (the reader is not shared); a Read of another frame drops
  // it.
  void Prefetch(uint32_t frame);
  // With the person network: masks only, no joint sightings (what a texture
  // needs; the sides' agreement across a dome's cameras costs more than the
  // network).
  void SkipSightings() { keep_sightings_ = false; }
  ~CaptureFrames();

  // Seconds spent so far decoding frames and running the person network
  // (decoding: what Read waited for).
  double decode_seconds() const { return decode_seconds_; }
  double person_seconds() const { return person_seconds_; }

 private:
  CaptureFrames(const Capture& capture, ThreadPool* pool) : reader_(capture), pool_(pool) {}
  Status ReadWithPersons(uint32_t frame, std::vector<Image>* images,
                         std::vector<Image>* silhouettes);
  // Every camera's image of `frame`: the prefetched ones, or decoded now.
  Status DecodeFrame(uint32_t frame, std::vector<Image>* read);

  CaptureReader reader_;
  ThreadPool* pool_;
  bool given_ = false;
  bool plates_ = false;
  std::vector<BackgroundModel> backgrounds_;
  PersonObserver* persons_ = nullptr;
  std::vector<PersonRegion> regions_;  // per camera, from its last frame (size 0: detect)
  std::vector<Camera> cameras_;        // with the network: the calibrations its sightings meet
  std::vector<std::vector<JointSighting>> sightings_;
  double decode_seconds_ = 0, person_seconds_ = 0;
  uint32_t ahead_frame_ = 0;
  bool keep_sightings_ = true;
  std::future<std::vector<StatusOr<Image>>> ahead_;  // Prefetch's, while valid()
  uint32_t side_exchanges_ = 0;
};

// The person network's joint sightings in frames `first`..`last` of every
// camera, `[frame - first][camera]`; `progress` (may be empty) hears every
// tenth frame.
using CaptureSightings = std::vector<std::vector<std::vector<JointSighting>>>;
StatusOr<CaptureSightings> ReadSightings(const Capture& capture, PersonObserver* persons,
                                         uint32_t first, uint32_t last,
                                         const std::function<void(const std::string&)>& progress);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_CAPTURE_FRAMES_H_

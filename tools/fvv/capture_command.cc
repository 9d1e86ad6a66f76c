#include "tools/fvv/capture_command.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "encoder/capture/calibration.h"
#include "encoder/capture/calibration_import.h"
#include "encoder/capture/capture.h"
#include "encoder/capture/colour_gain.h"
#include "encoder/capture/up_axis.h"
#include "encoder/capture/video_reader.h"
#include "encoder/io/image_io.h"
#include "encoder/shape/visual_hull.h"
#include "encoder/track/calibration_refinement.h"
#include "encoder/track/camera_sync.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/outline_hull.h"
#include "encoder/track/person_observer.h"
#include "encoder/track/silhouette_calibration.h"
#include "encoder/track/tangent_calibration.h"
#include "encoder/track/tangent_sync.h"
#include "encoder/track/track_capture.h"
#include "tools/fvv/calibrate_colour_command.h"
#include "tools/fvv/camera_names.h"
#include "tools/fvv/frame_range.h"
#include "tools/fvv/register_command.h"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

int Fail(const Status& s) {
  std::fprintf(stderr, "fvv: %s\n", s.ToString().c_str());
  return 1;
}

// The person network from `models` (empty: the default directory); `needed_by`
// starts the error ("sync needs the person network: ...").
StatusOr<std::unique_ptr<PersonObserver>> LoadPersons(const std::string& models,
                                                      const std::string& needed_by) {
  StatusOr<std::unique_ptr<PersonObserver>> o =
      PersonObserver::Load(models.empty() ? DefaultModelDirectory() : models);
  if (!o.ok() && !needed_by.empty()) {
    return Status(o.status().code(),
                  needed_by + " needs the person network: " + o.status().message());
  }
  return o;
}

int RunSynthCommand(SynthOptions o) {
  o.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  StatusOr<SynthSummary> s = RunSynth(o);
  if (!s.ok()) return Fail(s.status());
  std::printf("synthetic capture: %s\n", o.output_dir.c_str());
  std::printf("  actor:    %s\n", s->actor.c_str());
  const Camera& first = s->capture.cameras.front().calibration;
  if (o.rig.empty()) {
    std::printf("  cameras:  %zu at %ux%u, %u held out (truth/heldout)\n",
                s->capture.cameras.size(), first.width, first.height, o.held_out);
  } else {
    std::printf("  cameras:  %zu of %s, each at its own size (the first %ux%u)\n",
                s->capture.cameras.size(), o.rig.c_str(), first.width, first.height);
  }
  std::printf("  frames:   %u at %.3g fps\n", o.frames, o.fps);
  std::printf("  truth:    %s/truth (poses, 3D joints, silhouettes, texture)\n",
              o.output_dir.c_str());
  std::printf("  time:     %.1f s (%.2f s per frame)\n", s->seconds, s->seconds / o.frames);
  return 0;
}

struct SheetArgs {
  std::string capture, output;
  uint32_t frame = 0;
  bool silhouettes = false, persons = false;
  std::string models;
};

// The network's person mask tinted red over the image, its keypoints as green
// dots (grey where it thinks them hidden).
void DrawPerson(const PersonObservation& p, Image* image) {
  if (p.mask.pixels.size() * 3 == image->pixels.size()) {
    for (size_t i = 0; i < p.mask.pixels.size(); ++i) {
      const int a = p.mask.pixels[i];
      uint8_t* px = &image->pixels[3 * i];
      px[0] = static_cast<uint8_t>(px[0] + (255 - px[0]) * a / 510);
      px[1] = static_cast<uint8_t>(px[1] - px[1] * a / 510);
      px[2] = static_cast<uint8_t>(px[2] - px[2] * a / 510);
    }
  }
  const int r = std::max(2, static_cast<int>(image->width / 200));
  for (const PersonKeypoint& k : p.keypoints) {
    const uint8_t colour[3] = {static_cast<uint8_t>(k.visibility > 0.5 ? 40 : 160),
                               static_cast<uint8_t>(k.visibility > 0.5 ? 255 : 160),
                               static_cast<uint8_t>(k.visibility > 0.5 ? 40 : 160)};
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        const long x = std::lround(k.pixel.x()) + dx, y = std::lround(k.pixel.y()) + dy;
        if (x < 0 || y < 0 || x >= long(image->width) || y >= long(image->height)) continue;
        std::copy_n(colour, 3, &image->pixels[3 * (size_t(y) * image->width + size_t(x))]);
      }
    }
  }
}

int RunSheet(const SheetArgs& a) {
  StatusOr<Capture> c = LoadCapture(a.capture);
  if (!c.ok()) return Fail(c.status());
  CaptureReader reader(*c);
  std::unique_ptr<PersonObserver> observer;
  if (a.persons) {
    if (a.silhouettes) return Fail(InvalidArgument("--persons draws over images, not silhouettes"));
    StatusOr<std::unique_ptr<PersonObserver>> o = LoadPersons(a.models, "");
    if (!o.ok()) return Fail(o.status());
    observer = std::move(*o);
  }
  std::vector<Image> tiles;
  for (uint32_t i = 0; i < c->cameras.size(); ++i) {
    StatusOr<Image> img =
        a.silhouettes ? reader.ReadSilhouette(i, a.frame) : reader.ReadFrame(i, a.frame);
    if (!img.ok()) return Fail(img.status());
    if (observer) {
      StatusOr<PersonObservation> seen = observer->Observe(*img, nullptr);
      if (!seen.ok()) return Fail(seen.status());
      std::printf("  %-8s %s (score %.2f)\n", c->cameras[i].calibration.name.c_str(),
                  seen->found ? "person found" : "no person", seen->score);
      if (seen->found) DrawPerson(*seen, &*img);
    }
    tiles.push_back(std::move(*img));
  }
  Status s = WriteImage(a.output, MakeContactSheet(tiles));
  if (!s.ok()) return Fail(s);
  std::printf("contact sheet: %zu cameras at frame %u -> %s\n", tiles.size(), a.frame,
              a.output.c_str());
  return 0;
}

int RunCheck(const std::string& path) {
  StatusOr<Capture> c = LoadCapture(path);
  if (!c.ok()) return Fail(c.status());
  CaptureReader reader(*c);
  Status s = reader.CheckFiles();
  if (!s.ok()) return Fail(s);
  // Decode the first and last frame of every camera: sizes and formats.
  for (uint32_t i = 0; i < c->cameras.size(); ++i) {
    for (uint32_t f : {0u, c->frame_count - 1}) {
      StatusOr<Image> img = reader.ReadFrame(i, f);
      if (!img.ok()) return Fail(img.status());
    }
  }
  std::printf("capture %s: %zu cameras, %u frames at %.3g fps, up axis %s%s%s: OK\n", path.c_str(),
              c->cameras.size(), c->frame_count, c->frame_rate,
              c->declared_up_axis == 'z' ? "z (cameras below in fvv's y-up world)" : "y",
              reader.HasBackgrounds() ? ", background plates" : "",
              reader.HasSilhouettes() ? ", silhouettes" : "");
  const std::string upright = UprightWarning(c->cameras, c->declared_up_axis);
  if (!upright.empty()) std::fprintf(stderr, "warning: %s\n", upright.c_str());
  for (const CaptureCamera& cam : c->cameras) {
    const Camera& k = cam.calibration;
    const auto centre = k.Centre();
    std::string gain;
    if (!IsUnitGain(cam.colour_gain)) {
      char text[64];
      std::snprintf(text, sizeof(text), "  colour gain %.3f %.3f %.3f", cam.colour_gain[0],
                    cam.colour_gain[1], cam.colour_gain[2]);
      gain = text;
    }
    std::printf("  %-8s %ux%u  f=%.1f  centre (%.2f, %.2f, %.2f) m  %s%s\n", k.name.c_str(),
                k.width, k.height, k.fx, centre[0], centre[1], centre[2],
                cam.frames.kind == FrameSource::Kind::kVideo ? "video" : "images", gain.c_str());
  }
  return 0;
}

struct ImportArgs {
  std::vector<std::string> files;
  std::string output_dir;
  std::string images = "{camera}/%06d.png";
  std::string video;
  int64_t first = 0;
  uint32_t frame_count = 0;
  double fps = 0;  // 0: the videos' rate, or 25
  std::string unit = "m";
  std::string up = "auto";
};

std::string ForCamera(std::string pattern, const std::string& camera) {
  for (size_t i = pattern.find("{camera}"); i != std::string::npos;
       i = pattern.find("{camera}", i)) {
    pattern.replace(i, 8, camera);
    i += camera.size();
  }
  return pattern;
}

// The size of a camera's frames (the first image, or the video's stream) and,
// for a video, its frame count and rate; false where the frames are not there.
struct FramesFound {
  bool found = false;
  uint32_t width = 0, height = 0, frames = 0;
  double frame_rate = 0;
};

StatusOr<FramesFound> FindFrames(const Capture& c, const FrameSource& source) {
  FramesFound f;
  const std::string first = FramePath(c, source, 0);
  if (source.kind == FrameSource::Kind::kVideo) {
    if (access(first.c_str(), F_OK) != 0) return f;
    StatusOr<VideoInfo> info = ProbeVideo(first);
    if (!info.ok()) return info.status();
    f = {true, info->width, info->height, info->frames, info->frame_rate};
    return f;
  }
  if (access(first.c_str(), F_OK) != 0) return f;
  StatusOr<Image> image = ReadImage(first);
  if (!image.ok()) return image.status();
  f.found = true;
  f.width = image->width;
  f.height = image->height;
  return f;
}

int RunImportCalib(const ImportArgs& a) {
  const double unit = a.unit == "m" ? 1.0 : a.unit == "cm" ? 0.01 : a.unit == "mm" ? 0.001 : -1;
  if (unit < 0) return Fail(InvalidArgument("--translation-unit must be m, cm or mm"));
  StatusOr<ImportedCalibration> imported = ImportCalibrationFiles(a.files, unit);
  if (!imported.ok()) return Fail(imported.status());
  Capture c;
  c.directory = a.output_dir;
  const UpAxisChoice up =
      ChooseUpAxis(a.up, imported->up_axis, imported->format, imported->cameras);
  c.up_axis = up.axis;
  double video_rate = 0;
  uint32_t video_frames = 0;
  for (Camera& k : imported->cameras) {
    CaptureCamera cc;
    if (a.video.empty()) {
      cc.frames.path = ForCamera(a.images, k.name);
      cc.frames.first = a.first;
    } else {
      cc.frames.kind = FrameSource::Kind::kVideo;
      cc.frames.path = ForCamera(a.video, k.name);
    }
    // The frames say what size the images are; a calibration made for another
    // window (a sensor crop, a different recording mode) is kept but fitted.
    StatusOr<FramesFound> found = FindFrames(c, cc.frames);
    if (!found.ok()) return Fail(found.status());
    if (found->found) {
      std::string note;
      Status s = FitImageSize(found->width, found->height, &k, &note);
      if (!s.ok()) return Fail(s);
      if (!note.empty()) std::fprintf(stderr, "warning: %s\n", note.c_str());
      if (found->frames > 0) {
        if (video_frames != 0 && found->frames != video_frames) {
          std::fprintf(stderr,
                       "warning: camera %s's video has %u frames, an earlier one %u; "
                       "the capture takes the shorter\n",
                       k.name.c_str(), found->frames, video_frames);
        }
        video_frames = video_frames == 0 ? found->frames : std::min(video_frames, found->frames);
      }
      if (video_rate == 0) video_rate = found->frame_rate;
    } else if (k.width == 0 || k.height == 0) {
      return Fail(InvalidArgument("camera " + k.name + ": the calibration gives no image size, " +
                                  "and its frames are not at " + FramePath(c, cc.frames, 0) +
                                  " to take it from (--images or --video)"));
    } else {
      Status s = ValidateCalibration(k, "camera " + k.name);
      if (!s.ok()) return Fail(s);
    }
    cc.calibration = k;
    c.cameras.push_back(cc);
  }
  c.frame_rate = a.fps > 0 ? a.fps : video_rate > 0 ? video_rate : 25;
  c.frame_count = a.frame_count > 0 ? a.frame_count : video_frames;
  if (c.frame_count == 0 && a.video.empty() && !c.cameras.empty()) {
    // Count the first camera's consecutive frames on disk.
    while (c.frame_count < kMaxCaptureFrames) {
      std::ifstream probe(FramePath(c, c.cameras[0].frames, c.frame_count));
      if (!probe) break;
      ++c.frame_count;
    }
  }
  if (c.frame_count == 0) {
    return Fail(InvalidArgument("no frames found for camera \"" + c.cameras[0].calibration.name +
                                "\" at " + FramePath(c, c.cameras[0].frames, 0) +
                                "; give --frame-count (and --images or --video)"));
  }
  // Round trip through the parser: what we write must load.
  StatusOr<Capture> check = ParseCapture(CaptureToJson(c), c.directory);
  if (!check.ok()) return Fail(check.status());
  // Made only now, so that an import that fails leaves nothing behind.
  const Status made = MakeDirectories(a.output_dir);
  if (!made.ok() || !std::filesystem::is_directory(a.output_dir)) {
    return Fail(InvalidArgument("--output " + a.output_dir + ": cannot make the directory" +
                                (made.ok() ? "" : " (" + made.message() + ")")));
  }
  Status s = SaveCapture(c);
  if (!s.ok()) return Fail(s);
  std::printf(
      "imported %zu cameras (%s) from %zu file(s) -> %s/capture.json (%u frames at %.3g fps)\n",
      c.cameras.size(), imported->format.c_str(), a.files.size(), a.output_dir.c_str(),
      c.frame_count, c.frame_rate);
  std::printf("  up axis %c: %s\n", c.up_axis, up.reason.c_str());
  if (!up.warning.empty()) std::fprintf(stderr, "warning: up axis: %s\n", up.warning.c_str());
  for (const CaptureCamera& cc : c.cameras) {
    const Camera& k = cc.calibration;
    const std::array<double, 3> centre = k.Centre();
    std::printf("  %-8s %ux%u  f %.1f %.1f  c %.1f %.1f  centre (%.3f, %.3f, %.3f) m\n",
                k.name.c_str(), k.width, k.height, k.fx, k.fy, k.cx, k.cy, centre[0], centre[1],
                centre[2]);
  }
  return 0;
}

}  // namespace

// The outline hulls of the actor's masks (given silhouettes, or the person
// network's) in frames first..last, `[frame][camera]`; `who` starts the
// progress lines.
StatusOr<std::vector<std::vector<OutlineHull>>> ReadOutlines(const Capture& cap,
                                                             const std::string& models,
                                                             uint32_t first, uint32_t last,
                                                             const std::string& who) {
  std::string note;
  FVV_ASSIGN_OR_RETURN(
      std::unique_ptr<PersonObserver> persons,
      PersonsForCapture(cap, false, TrackCaptureOptions::Persons::kAuto, models, &note));
  if (!note.empty()) std::fprintf(stderr, "%s: %s\n", who.c_str(), note.c_str());
  ThreadPool pool(2);
  FVV_ASSIGN_OR_RETURN(std::unique_ptr<CaptureFrames> frames,
                       CaptureFrames::Open(cap, false, &pool, persons.get()));
  std::vector<std::vector<OutlineHull>> outlines;
  std::vector<Image> masks;
  for (uint32_t f = first; f <= last; ++f) {
    FVV_RETURN_IF_ERROR(frames->Read(f, nullptr, &masks));
    if (f < last) frames->Prefetch(f + 1);
    std::vector<OutlineHull> hulls;
    for (size_t c = 0; c < cap.cameras.size(); ++c) {
      hulls.push_back(MakeOutlineHull(cap.cameras[c].calibration, masks[c]));
    }
    outlines.push_back(std::move(hulls));
    if ((f - first) % 10 == 9 || f == last) {
      std::fprintf(stderr, "%s: outlines of frame %u (%u of %u; %s)\n", who.c_str(), f,
                   f - first + 1, last - first + 1, frames->silhouette_source().c_str());
    }
  }
  return outlines;
}

struct SyncArgs {
  std::string capture, frames = "0:59", models;
  std::string from = "keypoints";  // or "tangents"
  int max_offset = 0;              // 0: 8 frames from keypoints, 2 from tangents
  bool write = false;
};

// `cap` with each camera's frames starting later by its offset, and the frame
// count cut by the largest.
StatusOr<Capture> Offset(const Capture& cap, const std::vector<int>& offsets) {
  Capture out = cap;
  const int most = *std::max_element(offsets.begin(), offsets.end());
  for (size_t c = 0; c < out.cameras.size(); ++c) {
    out.cameras[c].frames.first += uint32_t(offsets[c]);
    if (out.cameras[c].silhouettes) out.cameras[c].silhouettes->first += uint32_t(offsets[c]);
  }
  if (out.frame_count <= uint32_t(most)) {
    return InvalidArgument("sync: offsets of up to " + std::to_string(most) +
                           " frames leave no frame of the capture");
  }
  out.frame_count -= uint32_t(most);
  return out;
}

// Offsets from the tangents of the actor's masks, on top of those the capture
// has: SyncFromTangents over the span, `range` frames either way.
int RunSyncFromTangents(const SyncArgs& a, const Capture& cap, uint32_t first, uint32_t last) {
  const uint32_t range = uint32_t(a.max_offset > 0 ? a.max_offset : 2);
  // Every candidate offset reads frames up to `range` either side of the span.
  const uint32_t from = std::max(first, range);
  const uint32_t to = cap.frame_count > range ? std::min(last, cap.frame_count - 1 - range) : 0;
  if (to < from + 2) {
    return Fail(
        InvalidArgument("sync: --frames " + a.frames + ": tangents compare 3 frames or more with " +
                        std::to_string(range) + " frames either side within the capture's " +
                        std::to_string(cap.frame_count) + " (--max-offset sets how many)"));
  }
  if (from != first || to != last) {
    std::fprintf(stderr, "sync: frames %u..%u compared (%u either side kept for the offsets)\n",
                 from, to, range);
  }
  first = from;
  last = to;
  StatusOr<std::vector<std::vector<OutlineHull>>> by_frame =
      ReadOutlines(cap, a.models, first - range, last + range, "sync");
  if (!by_frame.ok()) return Fail(by_frame.status());
  std::vector<std::vector<OutlineHull>> by_camera(cap.cameras.size());
  for (auto& frame : *by_frame) {
    for (size_t c = 0; c < frame.size(); ++c) by_camera[c].push_back(std::move(frame[c]));
  }
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : cap.cameras) cameras.push_back(c.calibration);
  TangentSyncOptions o;
  o.range = int(range);
  o.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  StatusOr<TangentSync> r = SyncFromTangents(cameras, by_camera, o);
  if (!r.ok()) return Fail(r.status());
  std::printf(
      "frame offsets of %s on top of capture.json's, from the tangents of the actor's masks in "
      "frames %u..%u (%d refinements; the tangents' cost %.3f as recorded, %.3f in step):\n",
      cap.directory.c_str(), first, last, r->evaluations, r->cost_before, r->cost_after);
  std::printf("  %-12s %8s\n", "camera", "offset");
  for (size_t c = 0; c < cameras.size(); ++c) {
    std::printf("  %-12s %8d\n", cameras[c].name.c_str(), r->offsets[c]);
  }
  if (*std::max_element(r->offsets.begin(), r->offsets.end()) == 0) {
    std::printf("the cameras run in step\n");
    return 0;
  }
  if (!a.write) {
    std::printf("(--write adds these offsets to capture.json's)\n");
    return 0;
  }
  StatusOr<Capture> out = Offset(cap, r->offsets);
  if (!out.ok()) return Fail(out.status());
  if (Status s = SaveCapture(*out); !s.ok()) return Fail(s);
  std::printf("wrote %s/capture.json: %u frames (was %u)\n", out->directory.c_str(),
              out->frame_count, cap.frame_count);
  return 0;
}

int RunSync(const SyncArgs& a) {
  StatusOr<Capture> cap = LoadCapture(a.capture);
  if (!cap.ok()) return Fail(cap.status());
  FrameOffsetOptions o;
  if (Status s = ParseFrameRange(a.frames, &o.first, &o.last); !s.ok()) return Fail(s);
  if (a.from == "tangents") return RunSyncFromTangents(a, *cap, o.first, o.last);
  o.max_offset = a.max_offset > 0 ? a.max_offset : 8;
  o.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  StatusOr<std::unique_ptr<PersonObserver>> observer = LoadPersons(a.models, "sync");
  if (!observer.ok()) return Fail(observer.status());
  StatusOr<FrameOffsets> r = EstimateFrameOffsets(*cap, observer->get(), o);
  if (!r.ok()) return Fail(r.status());
  std::printf(
      "frame offsets of %s (%u frames compared; keypoints against the other cameras', "
      "pixels):\n",
      cap->directory.c_str(), r->frames);
  std::printf("  %-12s %8s %12s %12s\n", "camera", "offset", "as recorded", "in step");
  int most = 0;
  for (size_t c = 0; c < cap->cameras.size(); ++c) {
    std::printf("  %-12s %8d %12.1f %12.1f\n", cap->cameras[c].calibration.name.c_str(),
                r->offsets[c], r->before_px[c], r->after_px[c]);
    most = std::max(most, r->offsets[c]);
  }
  if (most == 0) {
    std::printf("the cameras run in step\n");
    return 0;
  }
  if (!a.write) {
    std::printf(
        "(--write skips these frames at the start of each camera's recording in "
        "capture.json)\n");
    return 0;
  }
  StatusOr<Capture> out = Offset(*cap, r->offsets);
  if (!out.ok()) return Fail(out.status());
  if (Status s = SaveCapture(*out); !s.ok()) return Fail(s);
  std::printf(
      "wrote %s/capture.json: each camera's frames start later by its offset; %u frames "
      "(was %u)\n",
      out->directory.c_str(), out->frame_count, cap->frame_count);
  return 0;
}

struct RefineArgs {
  std::string capture, frames = "0:59", models;
  std::string from = "keypoints";    // or "silhouettes", "tangents"
  std::vector<std::string> cameras;  // refined among themselves; empty: all
  int rounds = SilhouetteCalibrationOptions{}.rounds;
  CalibrationRefinementOptions options;
  bool write = false;
};

// Per camera, the median over frames of its sightings' mean distance from the
// other cameras' triangulated (KeypointAgreement): -1 where never measured.
std::vector<double> HeldOutAgreement(const std::vector<Camera>& cameras,
                                     const CaptureSightings& seen) {
  std::vector<double> median(cameras.size(), -1);
  for (uint32_t k = 0; k < cameras.size(); ++k) {
    std::vector<double> v;
    for (const auto& frame : seen) {
      const double a = KeypointAgreement(cameras, k, frame, 20.0);
      if (a >= 0) v.push_back(a);
    }
    if (v.empty()) continue;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    median[k] = v[v.size() / 2];
  }
  return median;
}

// With --write, `cameras` (refined orientations of the chosen cameras) into
// capture.json; without, a hint.
int WriteOrientations(const RefineArgs& a, const Capture& cap, const std::vector<size_t>& chosen,
                      const std::vector<Camera>& cameras) {
  if (!a.write) {
    std::printf("(--write stores the refined orientations in capture.json)\n");
    return 0;
  }
  Capture out = cap;
  for (size_t i = 0; i < chosen.size(); ++i) {
    const Camera& k = cameras[i];
    if (Status s = ValidateCalibration(k, k.name); !s.ok()) return Fail(s);
    out.cameras[chosen[i]].calibration = k;
  }
  if (Status s = SaveCapture(out); !s.ok()) return Fail(s);
  std::printf("wrote %s/capture.json with the refined orientations\n", out.directory.c_str());
  return 0;
}

// Camera orientations from the outlines of the actor tracked with the chosen
// cameras (RefineCamerasFromSilhouettes); `sub` is the capture cut down to them.
int RunRefineFromSilhouettes(const RefineArgs& a, const Capture& cap, const Capture& sub,
                             const std::vector<size_t>& chosen, uint32_t first, uint32_t last) {
  SilhouetteCalibrationOptions o;
  o.first = first;
  o.last = last;
  o.rounds = a.rounds;
  o.track.person_models = a.models;
  o.progress = [](const std::string& line) {
    std::fprintf(stderr, "refine-calib: %s\n", line.c_str());
  };
  StatusOr<SilhouetteCalibration> r = RefineCamerasFromSilhouettes(sub, o);
  if (!r.ok()) return Fail(r.status());
  std::printf(
      "camera orientations of %s refined from the actor's outlines in frames %u..%u (%zu "
      "round(s); the fit's mean IoU %.3f in the first, %.3f in the last):\n",
      cap.directory.c_str(), first, last, r->rounds.size(), r->rounds.front().mean_iou,
      r->rounds.back().mean_iou);
  std::printf("  %-10s %24s %24s %10s\n", "camera", "first shift (IoU -> at it)",
              "last shift (IoU)", "turned");
  for (size_t c = 0; c < sub.cameras.size(); ++c) {
    const SilhouetteCalibrationRound &f = r->rounds.front(), &l = r->rounds.back();
    std::printf("  %-10s %+6.1f,%+6.1f px %.3f->%.3f %+6.1f,%+6.1f px %.3f %7.2f deg\n",
                sub.cameras[c].calibration.name.c_str(), f.shift_px[c].x(), f.shift_px[c].y(),
                f.iou[c], f.shifted_iou[c], l.shift_px[c].x(), l.shift_px[c].y(), l.iou[c],
                r->turn_deg[c]);
  }
  // No round turned a camera: the first round's shifts were all under stop_px.
  bool turned = false;
  for (size_t c = 0; c < sub.cameras.size(); ++c) {
    turned = turned || r->cameras[c].rotation != sub.cameras[c].calibration.rotation;
  }
  if (!turned) {
    std::printf("the outlines agree within %.0f pixels: capture.json left unchanged\n", o.stop_px);
    return 0;
  }
  return WriteOrientations(a, cap, chosen, r->cameras);
}

// Camera orientations from the tangents of every pair of cameras' masks
// (RefineCamerasFromTangents); `sub` is the capture cut down to the chosen
// cameras.
int RunRefineFromTangents(const RefineArgs& a, const Capture& cap, const Capture& sub,
                          const std::vector<size_t>& chosen, uint32_t first, uint32_t last) {
  StatusOr<std::vector<std::vector<OutlineHull>>> outlines =
      ReadOutlines(sub, a.models, first, last, "refine-calib");
  if (!outlines.ok()) return Fail(outlines.status());
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : sub.cameras) cameras.push_back(c.calibration);
  StatusOr<TangentCalibration> r = RefineCamerasFromTangents(cameras, *outlines);
  if (!r.ok()) return Fail(r.status());
  std::printf(
      "camera orientations of %s refined from the tangents of the actor's silhouettes in frames "
      "%u..%u (%d iterations; %d combination(s) of turns the tangents hardly measure left as "
      "calibrated):\n",
      cap.directory.c_str(), first, last, r->iterations, r->held_directions);
  std::printf("  %-10s %9s %20s %12s\n", "camera", "tangents", "median px", "turned");
  double most_gain = 0;
  for (size_t c = 0; c < cameras.size(); ++c) {
    std::printf("  %-10s %9u %8.2f -> %6.2f %8.3f deg\n", cameras[c].name.c_str(), r->tangents[c],
                r->before_px[c], r->after_px[c], r->turn_deg[c]);
    if (r->before_px[c] > 0) most_gain = std::max(most_gain, r->before_px[c] - r->after_px[c]);
  }
  // Under half a pixel is within what masks cut at pixels say.
  if (most_gain < 0.5) {
    std::printf(
        "no camera's tangents meet the others' half a pixel closer: the calibration agrees with "
        "the silhouettes as it is; capture.json left unchanged\n");
    return 0;
  }
  return WriteOrientations(a, cap, chosen, r->cameras);
}

int RunRefineCalib(const RefineArgs& a) {
  StatusOr<Capture> loaded = LoadCapture(a.capture);
  if (!loaded.ok()) return Fail(loaded.status());
  uint32_t first = 0, last = 0;
  if (Status s = ParseFrameRange(a.frames, &first, &last); !s.ok()) return Fail(s);
  last = std::min(last, loaded->frame_count - 1);
  StatusOr<std::vector<size_t>> chosen = ChooseCameras(*loaded, a.cameras);
  if (!chosen.ok()) return Fail(chosen.status());
  // The chosen cameras alone: the others take no part and keep their poses.
  Capture sub = *loaded;
  sub.cameras.clear();
  for (size_t c : *chosen) sub.cameras.push_back(loaded->cameras[c]);
  if (a.from == "silhouettes")
    return RunRefineFromSilhouettes(a, *loaded, sub, *chosen, first, last);
  if (a.from == "tangents") return RunRefineFromTangents(a, *loaded, sub, *chosen, first, last);
  StatusOr<std::unique_ptr<PersonObserver>> observer =
      LoadPersons(a.models, "refining the calibration");
  if (!observer.ok()) return Fail(observer.status());
  StatusOr<CaptureSightings> seen = ReadSightings(
      sub, observer->get(), first, last,
      [](const std::string& line) { std::fprintf(stderr, "refine-calib: %s\n", line.c_str()); });
  if (!seen.ok()) return Fail(seen.status());
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : sub.cameras) cameras.push_back(c.calibration);
  StatusOr<CalibrationRefinement> r = RefineCameraPoses(cameras, *seen, a.options);
  if (!r.ok()) return Fail(r.status());
  const std::vector<double> before = HeldOutAgreement(cameras, *seen),
                            after = HeldOutAgreement(r->cameras, *seen);
  std::printf(
      "camera poses of %s refined from the body keypoints of frames %u..%u (%u joints, %d "
      "iterations):\n",
      sub.directory.c_str(), first, last, r->points, r->iterations);
  std::printf("  %-10s %9s %16s %22s %10s %8s\n", "camera", "sightings", "median px",
              "against the others px", "turned", "moved");
  double most_turn = 0, most_move = 0;
  for (size_t c = 0; c < cameras.size(); ++c) {
    std::printf("  %-10s %9u %7.1f -> %5.1f %10.1f -> %7.1f %8.3f deg %5.0f mm\n",
                cameras[c].name.c_str(), r->sightings[c], r->before_px[c], r->after_px[c],
                before[c], after[c], r->rotation_deg[c], 1000 * r->centre_m[c]);
    most_turn = std::max(most_turn, r->rotation_deg[c]);
    most_move = std::max(most_move, r->centre_m[c]);
  }
  if (most_turn > 5 || most_move > 0.3) {
    return Fail(InvalidArgument(
        "refine-calib: a camera would turn or move further (" + std::to_string(most_turn) +
        " deg, " + std::to_string(most_move) +
        " m) than a knocked calibration does; the calibration is wrong in another way (another "
        "take's file, a unit, an axis convention), or the keypoints are (check with fvv capture "
        "sheet --persons); capture.json is unchanged"));
  }
  // Where no camera meets the others clearly better, the turns are what the
  // keypoints leave free, not what they say (docs/tracking.md).
  // A gain counts from 10 % and a pixel (less is within any keypoint's noise).
  double best_gain = 0;
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (before[c] > 0 && after[c] >= 0 && before[c] - after[c] >= 1.0) {
      best_gain = std::max(best_gain, 1 - after[c] / before[c]);
    }
  }
  if (best_gain < 0.1) {
    std::printf(
        "no camera's keypoints meet the others' 10 %% and a pixel closer: the calibration "
        "agrees with the keypoints as it is; capture.json left unchanged\n");
    return 0;
  }
  if (!a.write) {
    std::printf("(--write stores the refined poses in capture.json)\n");
    return 0;
  }
  Capture out = *loaded;
  for (size_t c = 0; c < chosen->size(); ++c) {
    if (Status s = ValidateCalibration(r->cameras[c], r->cameras[c].name); !s.ok()) return Fail(s);
    out.cameras[(*chosen)[c]].calibration = r->cameras[c];
  }
  if (Status s = SaveCapture(out); !s.ok()) return Fail(s);
  std::printf("wrote %s/capture.json with the refined camera poses\n", out.directory.c_str());
  return 0;
}

struct HullArgs {
  std::string capture, output;
  uint32_t frame = 0;
  VisualHullOptions options;
  bool extract = false;
};

int RunHull(const HullArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  StatusOr<Capture> cap = LoadCapture(a.capture);
  if (!cap.ok()) return Fail(cap.status());
  if (a.frame >= cap->frame_count) {
    return Fail(InvalidArgument("--frame " + std::to_string(a.frame) + ": the capture has " +
                                std::to_string(cap->frame_count) + " frames"));
  }
  ThreadPool pool(2);
  auto frames = CaptureFrames::Open(*cap, a.extract, &pool);
  if (!frames.ok()) return Fail(frames.status());
  std::vector<Image> silhouettes;
  if (Status s = (*frames)->Read(a.frame, nullptr, &silhouettes); !s.ok()) return Fail(s);
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : cap->cameras) cameras.push_back(c.calibration);
  StatusOr<VisualHull> hull = CarveVisualHull(cameras, silhouettes, a.options, pool.runner());
  if (!hull.ok()) return Fail(hull.status());
  const std::vector<Eigen::Vector3d> surface = hull->SurfaceVoxels();
  if (Status s = WritePointCloudPly(a.output, surface); !s.ok()) return Fail(s);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const Eigen::Vector3d& p : surface) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  std::printf(
      "visual hull of frame %u (%zu cameras, %s silhouettes): %zu voxels of %.1f cm, "
      "%.4f m^3, extent %.2f x %.2f x %.2f m; %zu surface voxels -> %s (%.2f s)\n",
      a.frame, cameras.size(), (*frames)->given_silhouettes() ? "given" : "extracted",
      hull->OccupiedCount(), 100 * a.options.voxel_size, hull->Volume(), hi.x() - lo.x(),
      hi.y() - lo.y(), hi.z() - lo.z(), surface.size(), a.output.c_str(),
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

void AddCaptureCommands(CLI::App* app, int* exit_code) {
  auto o = std::make_shared<SynthOptions>();
  CLI::App* s = app->add_subcommand(
      "synth", "Render a synthetic multi-view capture with ground truth (OpenGL, headless)");
  s->add_option("-o,--output", o->output_dir, "Output capture directory")->required();
  s->add_option("--cameras", o->cameras, "Ring cameras")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  s->add_flag("--overhead", o->overhead, "Add a camera looking down from above");
  s->add_option("--dome", o->dome,
                "A studio dome of N cameras instead of the ring: four rings from 0.5 m to 3.3 m "
                "high, every fifth camera of the lower three a close-up that sees the actor "
                "partly (docs/capture-format.md)")
      ->check(CLI::Range(4, 256));
  s->add_option("--width", o->width, "Image width")->capture_default_str();
  s->add_option("--height", o->height, "Image height")->capture_default_str();
  s->add_option("--fps", o->fps, "Frame rate")->capture_default_str();
  s->add_option("--frames", o->frames, "Frame count")->capture_default_str();
  s->add_option("--seed", o->seed, "Seed (noise, texture detail)")->capture_default_str();
  s->add_option("--motion", o->motion, "BVH motion file (default: a built-in walk)");
  s->add_option("--motion-start", o->motion_start, "Seconds into the BVH clip to start from")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  s->add_option("--actor", o->actor, "\"builtin\" or a glTF 2.0 character (.glb/.gltf)")
      ->capture_default_str();
  s->add_option("--stature", o->stature, "Built-in actor's size (1.0 = 1.75 m)")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 1.4));
  s->add_option("--surface-detail", o->surface_detail,
                "Built-in actor: bumps and hollows off the generic shape, up to this many metres "
                "(a true surface for shape refinement to recover)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.1));
  s->add_option("--garment", o->garment,
                "Built-in actor: loose shorts standing off the body by up to this many metres as "
                "the legs swing apart (the surface moves apart from the skeleton; the true "
                "surface of every frame goes into truth/surface_fFFFFFF.bin)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.1));
  s->add_option("--noise", o->noise, "Sensor noise (std. dev., 8-bit levels)")
      ->capture_default_str();
  s->add_option("--colour-mismatch", o->colour_mismatch, "Per-camera gain spread (0.05 = 5 %)")
      ->capture_default_str();
  s->add_flag("--unlit", o->unlit,
              "No shading on the actor: the camera images show the surface texture's own "
              "colours (to check texture resampling against truth/texture.png)");
  s->add_option("--held-out", o->held_out, "Extra cameras for novel-view evaluation")
      ->capture_default_str();
  s->add_flag("--with-silhouettes", o->link_silhouettes,
              "List the true silhouettes in capture.json (skip background subtraction)");
  s->add_flag_callback(
      "--no-plates", [o] { o->plates = false; },
      "Write no background plates (a studio that shot none: silhouettes come from the take)");
  s->add_flag("--clutter", o->clutter,
              "Furniture and equipment around the capture volume, as in a lab");
  s->add_flag("--bystander", o->bystander,
              "A second person walks through behind the actor (in the frames, not the truth)");
  s->add_option("--rig", o->rig,
                "Film with this capture's cameras instead of the ring (capture directory or "
                "capture.json): their positions, orientations, focal lengths and image sizes, "
                "calibrated exactly, lens distortion left out; moved on the floor so the actor "
                "stands where the optical axes meet (docs/capture-format.md)");
  s->add_option("--rig-poses", o->rig_poses,
                "With --rig: the built-in actor moves as this poses.json (fvv track on a take "
                "that rig filmed) says, in its fitted proportions, the rig moved to where it "
                "puts him");
  s->add_option("--calibration-error", o->calibration_error,
                "Degrees: each camera films turned by this much about an axis in its image plane "
                "(drawn from the seed) while capture.json records it unturned, a calibration off "
                "by about the focal length times this angle in pixels (truth.json: "
                "calibration_error)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  auto real_conditions = std::make_shared<bool>(false);
  s->add_flag(
      "--real-conditions", *real_conditions,
      "What broke on a real take: no plates, clutter, a bystander, 4 portrait cameras (360x640 "
      "unless --width, --height or --cameras say otherwise)");
  s->add_flag_callback(
      "--classic", [o] { o->width = 320, o->height = 240, o->fps = 15; },
      "320x240 at 15 fps, as in the original studio");
  s->callback([s, o, real_conditions, exit_code] {
    if (!o->rig.empty() && s->get_option("--cameras")->count() > 0) {
      std::fprintf(stderr, "fvv synth: --rig brings its own cameras: leave out --cameras\n");
      *exit_code = 2;
      return;
    }
    if (!o->rig.empty() && s->get_option("--held-out")->count() == 0) o->held_out = 0;
    if (*real_conditions) {
      o->plates = false, o->clutter = true, o->bystander = true;
      if (s->get_option("--cameras")->count() == 0) o->cameras = 4;
      if (s->get_option("--width")->count() == 0) o->width = 360;
      if (s->get_option("--height")->count() == 0) o->height = 640;
    }
    *exit_code = RunSynthCommand(*o);
  });

  CLI::App* cap = app->add_subcommand(
      "capture",
      "Capture directories: check, contact sheet, calibration import, frame sync, calibration "
      "refinement, colour calibration, visual hull, registration from feature points");
  cap->require_subcommand(1);
  auto check_path = std::make_shared<std::string>();
  CLI::App* check =
      cap->add_subcommand("check", "Validate a capture: calibration, files, frame sizes");
  check->add_option("capture", *check_path, "Capture directory or capture.json")->required();
  check->callback([check_path, exit_code] { *exit_code = RunCheck(*check_path); });

  auto sheet = std::make_shared<SheetArgs>();
  CLI::App* sh = cap->add_subcommand("sheet", "A contact sheet (PNG) of all cameras at one frame");
  sh->add_option("capture", sheet->capture, "Capture directory or capture.json")->required();
  sh->add_option("-o,--output", sheet->output, "Output image (.png or .exr)")->required();
  sh->add_option("--frame", sheet->frame, "Frame index")->capture_default_str();
  sh->add_flag("--silhouettes", sheet->silhouettes, "Show the capture's silhouettes instead");
  sh->add_flag("--persons", sheet->persons,
               "Draw the person the pretrained network sees: its mask (red) and 33 keypoints "
               "(green; grey where it thinks them hidden)");
  sh->add_option("--models", sheet->models,
                 "Directory of the person models (default: $FVV_MODEL_DIR or ~/.cache/fvv/models)");
  sh->callback([sheet, exit_code] { *exit_code = RunSheet(*sheet); });

  auto sync = std::make_shared<SyncArgs>();
  CLI::App* sy = cap->add_subcommand(
      "sync",
      "Whether the cameras run in step: frame offsets from the person network's body keypoints "
      "(each camera against the others, shifted by whole frames); --write stores them");
  sy->add_option("capture", sync->capture, "Capture directory or capture.json")->required();
  sy->add_option("--frames", sync->frames,
                 "Frames compared A:B (a span where the actor moves; at least 2 x "
                 "--max-offset + 2)")
      ->capture_default_str();
  sy->add_option("--max-offset", sync->max_offset,
                 "Largest offset looked for, frames (default: 8 from keypoints; from tangents 2, "
                 "either way of capture.json's offsets)")
      ->check(CLI::Range(1, 1000));
  sy->add_option("--from", sync->from,
                 "keypoints: offsets from the body keypoints; tangents: offsets on top of "
                 "capture.json's from the tangents of the actor's masks (refine-calib --from "
                 "tangents for each candidate; needs a calibration good to a few pixels: run it "
                 "after sync from keypoints)")
      ->capture_default_str()
      ->check(CLI::IsMember({"keypoints", "tangents"}));
  sy->add_flag("--write", sync->write,
               "Write the offsets into capture.json (each camera's frames 'first'; the frame "
               "count shrinks by the largest)");
  sy->add_option("--models", sync->models,
                 "Directory of the person models (default: $FVV_MODEL_DIR or ~/.cache/fvv/models)");
  sy->callback([sync, exit_code] { *exit_code = RunSync(*sync); });

  auto refine = std::make_shared<RefineArgs>();
  CLI::App* rc = cap->add_subcommand(
      "refine-calib",
      "Refine the camera poses from the person network's body keypoints (bundle adjustment "
      "over a span of frames; intrinsics kept) or the cameras' orientations from the tracked "
      "actor's outlines (--from silhouettes) or from the tangents of his masks (--from "
      "tangents); --write stores them. Bring the cameras in step (sync) first");
  rc->add_option("capture", refine->capture, "Capture directory or capture.json")->required();
  rc->add_option("--frames", refine->frames,
                 "Frames A:B whose keypoints, outlines or masks are used (the actor in view, "
                 "moving about)")
      ->capture_default_str();
  rc->add_option("--prior-rotation", refine->options.prior_rotation_deg,
                 "How far (degrees, one standard deviation) the calibration's orientations are "
                 "believed off")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 30.0));
  rc->add_option("--prior-centre", refine->options.prior_centre_m,
                 "How far (metres, one standard deviation) its camera centres are believed off")
      ->capture_default_str()
      ->check(CLI::Range(0.0001, 1.0));
  rc->add_option("--from", refine->from,
                 "keypoints: camera poses from the body keypoints (bundle adjustment); "
                 "silhouettes: orientations only, each camera turned by the one image shift that "
                 "lays the tracked body's outlines on its person masks, tracked again, for "
                 "--rounds rounds (docs/tracking.md); tangents: orientations only, all cameras "
                 "turned together until the lines through each other camera's centre that touch "
                 "one camera's person masks map to those that touch the other's (no body model)")
      ->capture_default_str()
      ->check(CLI::IsMember({"keypoints", "silhouettes", "tangents"}));
  rc->add_option("--cameras", refine->cameras,
                 "Refine these cameras among themselves (names, comma-separated); the others take "
                 "no part and keep their calibration (default: all)")
      ->delimiter(',');
  rc->add_option("--rounds", refine->rounds,
                 "With --from silhouettes: track-and-turn rounds at most (ends early when every "
                 "shift is under 2 pixels)")
      ->capture_default_str()
      ->check(CLI::Range(1, 20));
  rc->add_flag("--write", refine->write, "Write the refined poses into capture.json");
  rc->add_option("--models", refine->models,
                 "Directory of the person models (default: $FVV_MODEL_DIR or ~/.cache/fvv/models)");
  rc->callback([refine, exit_code] { *exit_code = RunRefineCalib(*refine); });

  auto imp = std::make_shared<ImportArgs>();
  CLI::App* ic = cap->add_subcommand(
      "import-calib",
      "Make capture.json from a studio's calibration: OpenCV FileStorage YAML, TOML (anipose, "
      "Pose2Sim, FreeMoCap), EasyMocap intri.yml + extri.yml, Qualisys .qca.txt. Image sizes "
      "come from the frames where they differ from the calibration's (with a warning)");
  ic->add_option("files", imp->files,
                 "Calibration files: one camera each, sections per camera, or files that complete "
                 "each other (EasyMocap's intri.yml and extri.yml)")
      ->required()
      ->check(CLI::ExistingFile);
  ic->add_option("-o,--output", imp->output_dir,
                 "Capture directory to write capture.json into (created if missing, once the "
                 "import has succeeded)")
      ->required();
  ic->add_option("--images", imp->images, "Frame pattern per camera ({camera} = its name)")
      ->capture_default_str();
  ic->add_option("--video", imp->video, "Video file per camera instead ({camera} = its name)");
  ic->add_option("--first", imp->first, "Number of the first image")->capture_default_str();
  ic->add_option("--frame-count", imp->frame_count,
                 "Frames (default: count the first camera's images)");
  ic->add_option("--fps", imp->fps, "Frame rate (default: the videos' rate, or 25)")
      ->check(CLI::PositiveNumber);
  ic->add_option("--translation-unit", imp->unit,
                 "Unit of t in the files: m, cm or mm (Qualisys files are always mm)")
      ->capture_default_str()
      ->check(CLI::IsMember({"m", "cm", "mm"}));
  ic->add_option("--up", imp->up,
                 "World up axis: y, z, or auto (the format's where it defines one, as Qualisys "
                 "does: z; else from the cameras, which stand upright above the floor)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "y", "z"}));
  ic->callback([imp, exit_code] { *exit_code = RunImportCalib(*imp); });

  auto hull = std::make_shared<HullArgs>();
  CLI::App* vh = cap->add_subcommand(
      "hull",
      "The visual hull of one frame: voxels carved by every camera's silhouette (given, or by "
      "background subtraction); writes its surface voxels as a PLY point cloud");
  vh->add_option("capture", hull->capture, "Capture directory or capture.json")->required();
  vh->add_option("-o,--output", hull->output, "Output point cloud (.ply)")->required();
  vh->add_option("--frame", hull->frame, "Frame index")->capture_default_str();
  vh->add_option("--voxel", hull->options.voxel_size, "Voxel size in metres")
      ->capture_default_str()
      ->check(CLI::Range(0.002, 0.2));
  vh->add_option("--margin", hull->options.margin_px,
                 "Pixels the silhouettes are taken to be larger (calibration and edge error)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 20.0));
  vh->add_flag("--extract", hull->extract,
               "Background subtraction even when the capture lists silhouettes");
  vh->callback([hull, exit_code] { *exit_code = RunHull(*hull); });
  AddRegisterCommand(cap, exit_code);
  AddCalibrateColourCommand(cap, exit_code);
}

}  // namespace fvv

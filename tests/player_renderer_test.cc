// Renderer II on OSMesa: draws the decoded model into a headless context.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_precision.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/vec3.hpp>

#include "conformance/sample/sample_stream.h"
#include "container/geometric_visibility.h"
#include "container/writer.h"
#include "encoder/io/image_io.h"
#include "fvv/fvv_decoder.hpp"
#include "player/render/headless.h"
#include "player/render/hud.h"
#include "player/render/renderer.h"

namespace fvv {
namespace {

constexpr int kW = 160, kH = 120;

struct Scene {
  DecoderPtr dec;
  std::unique_ptr<HeadlessContext> ctx;
  std::unique_ptr<Renderer> renderer;
  std::vector<fvv_camera> cameras;
  std::string path;  // the stream file
};

void MakeScene(Scene* s, uint16_t gop_cameras = 4, bool predictive = false, double bpp = 0.5) {
  SampleStreamOptions o = TinySampleOptions();
  o.cameras = 4;
  o.gop_cameras = gop_cameras;
  o.atlas_width = o.atlas_height = 32;
  o.bpp = bpp;
  if (predictive) o.predictive = true, o.kernel = WaveletKernel::kLeGall53;
  auto bytes = MakeSampleStreamBytes(o);
  ASSERT_TRUE(bytes.ok());
  const std::string path = ::testing::TempDir() + "/fvv_renderer_test_" +
                           std::to_string(gop_cameras) + (predictive ? "_predictive" : "") + "_" +
                           std::to_string(getpid()) + ".fvv";
  ASSERT_TRUE(WriteFileAtomic(path, bytes->data(), bytes->size()).ok());
  s->path = path;
  s->dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(s->dec.get(), path.c_str()), FVV_OK);
  auto ctx = HeadlessContext::Create(kW, kH);
  ASSERT_TRUE(ctx.ok()) << ctx.status().ToString();
  s->ctx = std::move(ctx).value();
  fvv_model model;
  ASSERT_EQ(fvv_decoder_get_model(s->dec.get(), &model), FVV_OK);
  s->cameras.resize(4);
  for (uint32_t c = 0; c < 4; ++c) {
    ASSERT_EQ(fvv_decoder_get_camera(s->dec.get(), c, &s->cameras[c]), FVV_OK);
  }
  auto r = Renderer::Create(s->ctx->gl(), model, s->cameras, 32, 32);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  s->renderer = std::move(r).value();
}

std::vector<uint8_t> RenderFromCamera(Scene* s, uint32_t frame_index, int camera) {
  FramePtr frame = DecodeFrame(s->dec.get(), frame_index, nullptr);
  EXPECT_TRUE(frame);
  if (!frame) return {};
  EXPECT_TRUE(s->renderer->SetFrame(*frame).ok());
  RenderView view;
  CameraViewProjection(s->cameras[camera], 0.05f, 50.0f, &view.view, &view.projection);
  view.eye = glm::vec3(s->cameras[camera].centre[0], s->cameras[camera].centre[1],
                       s->cameras[camera].centre[2]);
  EXPECT_TRUE(s->renderer->Draw(view, kW, kH).ok());
  std::vector<uint8_t> rgb;
  EXPECT_TRUE(s->renderer->ReadRgb(kW, kH, &rgb).ok());
  return rgb;
}

size_t ForegroundPixels(const std::vector<uint8_t>& rgb, const RenderView& v) {
  const uint8_t bg[3] = {uint8_t(v.background.r * 255 + 0.5f), uint8_t(v.background.g * 255 + 0.5f),
                         uint8_t(v.background.b * 255 + 0.5f)};
  size_t n = 0;
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
    n += std::abs(rgb[i] - bg[0]) + std::abs(rgb[i + 1] - bg[1]) + std::abs(rgb[i + 2] - bg[2]) > 6;
  }
  return n;
}

TEST(Renderer, DrawsTheActorFromACaptureCamera) {
  Scene s;
  MakeScene(&s);
  if (HasFatalFailure()) return;
  const std::vector<uint8_t> a = RenderFromCamera(&s, 0, 0);
  ASSERT_EQ(a.size(), size_t{kW} * kH * 3);
  const size_t fg = ForegroundPixels(a, RenderView());
  // The stick figure covers a few percent of the view, not nothing and not all.
  EXPECT_GT(fg, size_t{kW} * kH / 100);
  EXPECT_LT(fg, size_t{kW} * kH / 3);
  // Deterministic, and other viewpoints / poses give other images.
  EXPECT_EQ(RenderFromCamera(&s, 0, 0), a);
  EXPECT_NE(RenderFromCamera(&s, 0, 1), a);
  EXPECT_NE(RenderFromCamera(&s, 2, 0), a);
}

// A stream with the predictive texture ('ptex', format version 2) plays like
// the SPIHT one: the same views within coding error.
TEST(Renderer, PredictiveTextureStreamsRenderLikeSpihtOnes) {
  Scene spiht, predictive;
  MakeScene(&spiht, 4, false, 2.0);
  if (HasFatalFailure()) return;
  MakeScene(&predictive, 4, true, 2.0);
  if (HasFatalFailure()) return;
  for (uint32_t frame : {0u, 2u}) {
    const std::vector<uint8_t> a = RenderFromCamera(&spiht, frame, 1);
    const std::vector<uint8_t> b = RenderFromCamera(&predictive, frame, 1);
    ASSERT_EQ(a.size(), b.size());
    double sse = 0;
    for (size_t i = 0; i < a.size(); ++i) sse += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
    const double psnr = 10 * std::log10(255.0 * 255.0 * a.size() / std::max(sse, 1e-9));
    std::printf("  frame %u: predictive vs SPIHT render %.2f dB\n", frame, psnr);
    EXPECT_GT(psnr, 30);
    EXPECT_GT(ForegroundPixels(b, RenderView()), size_t{kW} * kH / 100);
  }
}

TEST(Renderer, RefusesMismatchedFramesAndEarlyDraws) {
  Scene s;
  MakeScene(&s);
  if (HasFatalFailure()) return;
  EXPECT_EQ(s.renderer->Draw(RenderView(), kW, kH).code(), StatusCode::kInvalidArgument);
  FramePtr frame = DecodeFrame(s.dec.get(), 0, nullptr);
  ASSERT_TRUE(frame);
  fvv_frame wrong = *frame;
  wrong.camera_count = 3;
  EXPECT_EQ(s.renderer->SetFrame(wrong).code(), StatusCode::kInvalidArgument);
  fvv_decode_budget yuv{};
  yuv.format = FVV_FORMAT_YUV444;
  FramePtr yuv_frame = DecodeFrame(s.dec.get(), 0, &yuv);
  ASSERT_TRUE(yuv_frame);
  EXPECT_EQ(s.renderer->SetFrame(*yuv_frame).code(), StatusCode::kInvalidArgument);
}

// A frame decoded with only the cameras the view blends (one camera per
// fragment) renders like the full frame; cameras left out take no part.
TEST(Renderer, FramesWithOnlyTheViewsCamerasRenderLikeFullOnes) {
  Scene s;
  MakeScene(&s, /*gop_cameras=*/1);
  if (HasFatalFailure()) return;
  std::vector<glm::vec3> centres;
  for (const fvv_camera& c : s.cameras) centres.emplace_back(c.centre[0], c.centre[1], c.centre[2]);
  const std::vector<uint8_t> full = RenderFromCamera(&s, 1, 0);
  FramePtr probe = DecodeFrame(s.dec.get(), 1, nullptr);
  ASSERT_TRUE(probe);
  const glm::vec3 root(probe->bone_world[12], probe->bone_world[13], probe->bone_world[14]);
  fvv_decode_budget budget{};
  budget.camera_mask = ViewCameras(centres, centres[0], root);
  EXPECT_EQ(budget.camera_mask, 0b1011u);  // camera 2, behind the actor, is left out
  DecoderPtr dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), s.path.c_str()), FVV_OK);
  FramePtr part = DecodeFrame(dec.get(), 1, &budget);
  ASSERT_TRUE(part);
  ASSERT_EQ(part->views[2].pixels, nullptr);
  ASSERT_TRUE(s.renderer->SetFrame(*part).ok());
  RenderView view;
  CameraViewProjection(s.cameras[0], 0.05f, 50.0f, &view.view, &view.projection);
  view.eye = centres[0];
  ASSERT_TRUE(s.renderer->Draw(view, kW, kH).ok());
  std::vector<uint8_t> rgb;
  ASSERT_TRUE(s.renderer->ReadRgb(kW, kH, &rgb).ok());
  ASSERT_EQ(rgb.size(), full.size());
  double diff = 0;
  for (size_t i = 0; i < rgb.size(); ++i) diff += std::abs(int(rgb[i]) - int(full[i]));
  const size_t fg = ForegroundPixels(full, RenderView());
  EXPECT_LT(diff / (3.0 * fg), 1.0) << "mean difference per actor pixel and channel";
  // Leaving out the camera the view looks through must change the image: the
  // renderer keeps the last full frame's texture of it, and must not use it.
  fvv_decode_budget no0{};
  no0.camera_mask = 0b1110u;
  FramePtr without = DecodeFrame(dec.get(), 1, &no0);
  ASSERT_TRUE(without);
  ASSERT_TRUE(s.renderer->SetFrame(*probe).ok());  // every texture of frame 1 uploaded
  ASSERT_TRUE(s.renderer->SetFrame(*without).ok());
  ASSERT_TRUE(s.renderer->Draw(view, kW, kH).ok());
  ASSERT_TRUE(s.renderer->ReadRgb(kW, kH, &rgb).ok());
  EXPECT_NE(rgb, full);
  // A frame without any camera's texture cannot be drawn.
  fvv_frame empty = *part;
  std::vector<fvv_view> none(part->camera_count, fvv_view{nullptr, nullptr});
  empty.views = none.data();
  EXPECT_EQ(s.renderer->SetFrame(empty).code(), StatusCode::kInvalidArgument);
}

// A frame of the scene's stream as a stream without masks would decode it;
// with `colours`, camera k's texture is one colour (colours[k]).
struct MasklessFrame {
  FramePtr decoded;
  fvv_frame frame{};
  std::vector<fvv_view> views;
  std::vector<std::vector<uint8_t>> solid;
};
void MakeMaskless(Scene* s, uint32_t index, const std::vector<glm::u8vec3>* colours,
                  MasklessFrame* m) {
  m->decoded = DecodeFrame(s->dec.get(), index, nullptr);
  ASSERT_TRUE(m->decoded);
  m->frame = *m->decoded;
  m->views.assign(m->frame.views, m->frame.views + m->frame.camera_count);
  m->solid.resize(m->views.size());
  for (size_t c = 0; c < m->views.size(); ++c) {
    m->views[c].mask = nullptr;
    if (!colours) continue;
    m->solid[c].resize(size_t(m->frame.width) * m->frame.height * 3);
    for (size_t i = 0; i < m->solid[c].size(); ++i) m->solid[c][i] = (*colours)[c][int(i % 3)];
    m->views[c].pixels = m->solid[c].data();
  }
  m->frame.views = m->views.data();
}

// Without masks the renderer draws each camera's depth map of the posed
// model on the GPU, from the simplified body (depth_map_triangles.h): the same
// surface at the same depth, within a centimetre, as a CPU rasterisation of
// the frame's whole skinned mesh through the camera's pinhole, row 0 at the top.
TEST(Renderer, WithoutMasksTheDepthMapsAreTheCamerasViewsOfThePosedModel) {
  Scene s;
  MakeScene(&s);
  if (HasFatalFailure()) return;
  MasklessFrame m;
  MakeMaskless(&s, 1, nullptr, &m);
  if (HasFatalFailure()) return;
  ASSERT_TRUE(s.renderer->SetFrame(m.frame).ok());
  for (uint32_t k = 0; k < 4; ++k) {  // each view draws the maps of the cameras it blends
    RenderView view;
    CameraViewProjection(s.cameras[k], 0.05f, 50.0f, &view.view, &view.projection);
    view.eye = glm::vec3(s.cameras[k].centre[0], s.cameras[k].centre[1], s.cameras[k].centre[2]);
    ASSERT_TRUE(s.renderer->Draw(view, kW, kH).ok());
  }
  ASSERT_NE(s.renderer->depth_maps(), nullptr);
  EXPECT_EQ(s.renderer->depth_map_layers(), 4u);  // each camera's map once for the frame
  fvv_model model;
  ASSERT_EQ(fvv_decoder_get_model(s.dec.get(), &model), FVV_OK);
  std::vector<glm::vec3> posed(model.vertex_count);
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    glm::mat4 skin(0.0f);
    for (int j = 0; j < 4; ++j) {
      skin += model.weights[4 * v + j] *
              glm::make_mat4(m.frame.bone_skin + 16 * size_t(model.joints[4 * v + j]));
    }
    posed[v] = glm::vec3(skin * glm::vec4(glm::make_vec3(model.positions + 3 * size_t(v)), 1));
  }
  CameraDepthMaps& maps = *s.renderer->depth_maps();
  for (uint32_t k = 0; k < 4; ++k) {
    std::vector<float> gpu;
    ASSERT_TRUE(maps.ReadLayer(k, &gpu).ok());
    const fvv_camera& c = s.cameras[k];
    const double sx = double(maps.width()) / c.width, sy = double(maps.height()) / c.height;
    std::vector<double> px(2 * posed.size());
    std::vector<float> inv_z(posed.size());
    for (size_t v = 0; v < posed.size(); ++v) {
      double q[3];
      for (int r = 0; r < 3; ++r) {
        q[r] = c.rotation[3 * r] * posed[v].x + c.rotation[3 * r + 1] * posed[v].y +
               c.rotation[3 * r + 2] * posed[v].z + c.translation[r];
      }
      inv_z[v] = q[2] > 1e-6 ? float(1 / q[2]) : 0.0f;
      px[2 * v] = (c.fx * q[0] / q[2] + c.cx + 0.5) * sx - 0.5;
      px[2 * v + 1] = (c.fy * q[1] / q[2] + c.cy + 0.5) * sy - 0.5;
    }
    const std::vector<float> cpu = RasterizeDepth(model.triangles, model.triangle_count, px.data(),
                                                  inv_z.data(), maps.width(), maps.height());
    size_t both = 0, either = 0, close = 0;
    for (size_t i = 0; i < cpu.size(); ++i) {
      const bool a = gpu[i] < 1e8f, b = std::isfinite(cpu[i]);
      either += a || b;
      if (!(a && b)) continue;
      ++both;
      close += std::abs(gpu[i] - cpu[i]) < 0.01f;
    }
    std::printf("  camera %u: %zu texels covered by both, %zu by one only; %zu within 1 cm\n", k,
                both, either - both, close);
    EXPECT_GT(both, size_t{200});
    EXPECT_GT(double(both), 0.9 * double(either));  // outlines differ by rasterisation only
    EXPECT_GT(double(close), 0.98 * double(both));
  }
}

// Without masks a camera textures what its depth map shows it: drawn from
// camera k's own pose with one colour per camera and no facing weight, the
// actor is camera k's colour (the camera on the viewing ray outweighs every
// other one wherever it sees the surface); were the visibility lost, the
// best-facing camera's fallback would show other colours on much of it.
TEST(Renderer, WithoutMasksTheViewsOwnCameraTexturesWhatItSees) {
  Scene s;
  MakeScene(&s);
  if (HasFatalFailure()) return;
  const std::vector<glm::u8vec3> colours = {
      {230, 40, 40}, {40, 230, 40}, {40, 40, 230}, {230, 230, 40}};
  MasklessFrame m;
  MakeMaskless(&s, 2, &colours, &m);
  if (HasFatalFailure()) return;
  for (uint32_t k = 0; k < 4; ++k) {
    ASSERT_TRUE(s.renderer->SetFrame(m.frame).ok());
    RenderView view;
    view.facing_exponent = 0;
    CameraViewProjection(s.cameras[k], 0.05f, 50.0f, &view.view, &view.projection);
    view.eye = glm::vec3(s.cameras[k].centre[0], s.cameras[k].centre[1], s.cameras[k].centre[2]);
    ASSERT_TRUE(s.renderer->Draw(view, kW, kH).ok());
    std::vector<uint8_t> rgb;
    ASSERT_TRUE(s.renderer->ReadRgb(kW, kH, &rgb).ok());
    size_t actor = 0, own = 0;
    for (size_t i = 0; i < rgb.size(); i += 3) {
      bool camera_colour = false, is_own = false;
      for (size_t c = 0; c < colours.size(); ++c) {
        const bool match = std::abs(rgb[i] - colours[c].r) + std::abs(rgb[i + 1] - colours[c].g) +
                               std::abs(rgb[i + 2] - colours[c].b) <=
                           12;
        camera_colour = camera_colour || match;
        is_own = is_own || (match && c == k);
      }
      // Blends of several colours at the outlines count as the actor too.
      const bool background =
          std::abs(rgb[i] - 31) + std::abs(rgb[i + 1] - 31) + std::abs(rgb[i + 2] - 36) <= 6;
      actor += camera_colour || !background;
      own += is_own;
    }
    std::printf("  camera %u: %zu actor pixels, %zu in its own colour\n", k, actor, own);
    EXPECT_GT(actor, size_t{kW} * kH / 100);
    EXPECT_GT(double(own), 0.98 * double(actor));  // measured 99.9-100 %
  }
}

}  // namespace
}  // namespace fvv

namespace fvv {
namespace {

// Of a dome's many cameras a view blends and decodes the closest few: a ring
// of 32 seen from camera 0's side keeps exactly the kMaxViewCameras closest in
// angle, however many lie within the angle asked; a ring of 8 keeps those
// within it as before.
TEST(ViewCameras, ADomeIsCutToTheClosestFew) {
  auto ring = [](int n) {
    std::vector<glm::vec3> centres;
    for (int c = 0; c < n; ++c) {
      const float a = 6.2831853f * float(c) / float(n);
      centres.emplace_back(3.0f * std::sin(a), 1.5f, 3.0f * std::cos(a));
    }
    return centres;
  };
  const glm::vec3 target(0.0f, 1.0f, 0.0f);
  const std::vector<glm::vec3> dome = ring(32);
  const glm::vec3 eye = target + 1.2f * (dome[0] - target);
  const uint64_t mask = ViewCameras(dome, eye, target, 110.0f);
  EXPECT_EQ(__builtin_popcountll(mask), kMaxViewCameras);
  // The closest: camera 0 and its neighbours out to 3 on either side, and
  // one of the two 4 away.
  for (int d = -3; d <= 3; ++d) EXPECT_TRUE((mask >> ((32 + d) % 32)) & 1) << d;
  EXPECT_EQ(((mask >> 4) & 1) + ((mask >> 28) & 1), 1u);
  // Without the cap, every camera within 110 degrees (19 of them).
  EXPECT_EQ(__builtin_popcountll(ViewCameras(dome, eye, target, 110.0f, 3, 64)), 19);
  const std::vector<glm::vec3> eight = ring(8);
  EXPECT_EQ(ViewCameras(eight, target + (eight[0] - target), target, 100.0f), 0b11000111u);
  // At least the 3 closest, however narrow the angle.
  EXPECT_EQ(__builtin_popcountll(ViewCameras(dome, eye, target, 1.0f)), 3);
}

// The HUD draws exactly its font's pixels, scaled, on its panel, and nothing
// outside the panel; unknown characters draw as '?'.
TEST(Hud, DrawsEveryFontPixelOnItsPanelAndNothingElse) {
  constexpr int kHudW = 400, kHudH = 90;  // the longest line fits at scale 2
  auto ctx = HeadlessContext::Create(kHudW, kHudH);
  ASSERT_TRUE(ctx.ok()) << ctx.status().ToString();
  const GlApi& gl = (*ctx)->gl();
  auto hud = HudOverlay::Create(gl);
  ASSERT_TRUE(hud.ok()) << hud.status().ToString();
  const std::vector<std::string> lines = {"fps 59.9 | decode 312 ms/GOP", "bytes 45% (120/260 KB)",
                                          "q Y7 U6 V6 ~"};
  for (int scale : {1, 2}) {
    gl.Viewport(0, 0, kHudW, kHudH);
    gl.ClearColor(1.0f, 0.0f, 1.0f, 1.0f);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ASSERT_TRUE((*hud)->Draw(lines, kHudW, kHudH, scale).ok());
    std::vector<uint8_t> rgb;
    ASSERT_TRUE(ReadFramebuffer(gl, kHudW, kHudH, 3, &rgb).ok());
    int panel_w, panel_h;
    HudOverlay::PanelSize(lines, scale, &panel_w, &panel_h);
    int text = 0, panel = 0, outside_changed = 0, lit = 0;
    for (int y = 0; y < kHudH; ++y) {
      for (int x = 0; x < kHudW; ++x) {
        const uint8_t* p = &rgb[(size_t(y) * kHudW + x) * 3];
        const bool inside = x < panel_w && y < panel_h;
        const bool magenta = p[0] == 255 && p[1] == 0 && p[2] == 255;
        if (!inside) {
          outside_changed += !magenta;
        } else if (p[1] > 200 && p[0] < 120) {
          ++text;
        } else if (p[0] < 30 && p[1] < 30 && p[2] < 40) {
          ++panel;
        }
      }
    }
    for (const std::string& l : lines) lit += HudOverlay::LitPixels(l);
    EXPECT_EQ(text, lit * scale * scale) << "scale " << scale;
    EXPECT_EQ(text + panel, std::min(panel_w, kHudW) * std::min(panel_h, kHudH))
        << "scale " << scale;
    EXPECT_EQ(outside_changed, 0);
  }
  EXPECT_EQ(HudOverlay::LitPixels("~"), HudOverlay::LitPixels("?"));
  EXPECT_EQ(HudOverlay::LitPixels("ms"), HudOverlay::LitPixels("MS"));
}

}  // namespace
}  // namespace fvv

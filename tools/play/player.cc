#include "tools/play/player.h"

// GL declarations come from glcorearb.h (gl_api.h), not from GLFW.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "encoder/io/image_io.h"
#include "fvv/fvv_decoder.hpp"
#include "player/playback/playback_loop.h"
#include "player/render/hud.h"
#include "player/render/renderer.h"

namespace fvv {
namespace {

const char kControls[] =
    "Controls:\n"
    "  left drag   orbit            right drag  pan            scroll   zoom\n"
    "  space       play / pause     left/right  step a frame   home/end first / last frame\n"
    "  pageup/pagedown  seek 1 s    L           loop on/off    +/-      speed x2 / /2\n"
    "  1..9        a capture camera's viewpoint (0: free orbit)\n"
    "  E/D         blend exponent up/down (higher: the best camera dominates)\n"
    "  H           HUD on/off\n"
    "  A           decode all cameras / only the cameras the view blends (the default)\n"
    "  esc, Q      quit\n"
    "The HUD (and the title bar) shows fps, decode ms per GOP and its budget, bytes decoded of\n"
    "bytes available and the bitplanes reached (the quality level); when decoding cannot keep\n"
    "up, fewer bytes of each GOP are decoded, never fewer than the quality floor (--floor);\n"
    "when even the floor takes longer than a GOP plays, playback slows down and the HUD says so.\n";

struct State {
  Transport* t = nullptr;  // the playback loop's playhead, play/pause, loop, speed
  float yaw = 0, pitch = 0.15f, distance = 3.5f;
  glm::vec3 pan{0.0f};
  float exponent = float(geometric_visibility::kViewExponent);
  int camera = -1;
  bool hud = true;
  bool* all_cameras = nullptr;
  bool dragging_left = false, dragging_right = false;
  bool dirty = true;  // the view or the controls changed: draw again
  double last_x = 0, last_y = 0;
  uint32_t frames = 1;
  double fps = 25;
};

// The on-screen HUD: playback, decoding against its budget, and the quality
// reached (bytes and bitplanes of the embedded streams).
std::vector<std::string> HudLines(const PlaybackLoop& loop, uint32_t frames, double fps,
                                  const State& s, int cameras_decoded, int cameras) {
  const Transport& t = *s.t;
  const fvv_decode_report& r = loop.report();
  const double budget_ms = r.max_ms_per_gop;  // what the GOP on screen was decoded under
  char line[5][128];
  std::snprintf(line[0], sizeof(line[0]), "frame %u/%u  %.0f fps  x%.2g%s", loop.frame_index() + 1,
                frames, fps, t.speed, t.playing ? "" : "  [paused]");
  std::snprintf(
      line[1], sizeof(line[1]), "decode %.0f ms/GOP  budget %s  floor %.0f%%", r.decode_ms,
      budget_ms > 0 ? (std::to_string(int(std::lround(budget_ms))) + " ms").c_str() : "full",
      100 * loop.controller().floor_share());
  std::snprintf(line[2], sizeof(line[2]), "bytes %.0f/%.0f KB (%.0f%%)  planes Y%u U%u V%u",
                r.bytes_decoded / 1024.0, r.bytes_available / 1024.0,
                r.bytes_available ? 100.0 * r.bytes_decoded / r.bytes_available : 100.0,
                r.bitplanes[0], r.bitplanes[1], r.bitplanes[2]);
  // Which cameras are decoded: all, or at most the controller's limit (the
  // start's three until a GOP is timed, then what the decoding time allows).
  std::string decoded;
  if (*s.all_cameras) {
    decoded = " (all)";
  } else if (const uint32_t most = loop.controller().max_cameras()) {
    decoded = " (at most " + std::to_string(most) +
              (loop.stats().gops ? ": decoding time)" : " until a GOP is timed)");
  }
  std::snprintf(line[3], sizeof(line[3]), "exponent %.1f  %s  cameras %d/%d%s", s.exponent,
                s.camera >= 0 ? ("camera " + std::to_string(s.camera + 1)).c_str() : "orbit",
                cameras_decoded, cameras, decoded.c_str());
  std::vector<std::string> lines = {line[0], line[1], line[2], line[3]};
  if (loop.controller().below_real_time()) {
    lines.push_back(loop.controller().at_floor()
                        ? "slower than real time: decoding only the quality floor"
                        : "slower than real time: cutting the budget");
  }
  return lines;
}

State* StateOf(GLFWwindow* w) { return static_cast<State*>(glfwGetWindowUserPointer(w)); }

void OnKey(GLFWwindow* w, int key, int, int action, int) {
  if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
  State& s = *StateOf(w);
  s.dirty = true;
  Transport& t = *s.t;
  switch (key) {
    case GLFW_KEY_H:
      s.hud = !s.hud;
      break;
    case GLFW_KEY_A:
      *s.all_cameras = !*s.all_cameras;
      break;
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
      glfwSetWindowShouldClose(w, 1);
      break;
    case GLFW_KEY_SPACE:
      t.playing = !t.playing;
      break;
    case GLFW_KEY_RIGHT:
      t.playing = false;
      t.playhead = std::floor(t.playhead) + 1;
      break;
    case GLFW_KEY_LEFT:
      t.playing = false;
      t.playhead = std::floor(t.playhead) - 1;
      break;
    case GLFW_KEY_HOME:
      t.playhead = 0;
      break;
    case GLFW_KEY_END:
      t.playhead = s.frames - 1;
      break;
    case GLFW_KEY_PAGE_UP:
      t.playhead += s.fps;
      break;
    case GLFW_KEY_PAGE_DOWN:
      t.playhead -= s.fps;
      break;
    case GLFW_KEY_L:
      t.loop = !t.loop;
      break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
      t.speed = std::min(8.0, t.speed * 2);
      break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
      t.speed = std::max(0.125, t.speed / 2);
      break;
    case GLFW_KEY_E:
      s.exponent = std::min(64.0f, s.exponent * 1.5f);
      break;
    case GLFW_KEY_D:
      s.exponent = std::max(0.25f, s.exponent / 1.5f);
      break;
    default:
      if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) s.camera = key - GLFW_KEY_0 - 1;
  }
  if (t.playhead < 0) t.playhead = 0;
  if (t.playhead > s.frames - 1) t.playhead = s.frames - 1;
}

void OnButton(GLFWwindow* w, int button, int action, int) {
  State& s = *StateOf(w);
  glfwGetCursorPos(w, &s.last_x, &s.last_y);
  if (button == GLFW_MOUSE_BUTTON_LEFT) s.dragging_left = action == GLFW_PRESS;
  if (button == GLFW_MOUSE_BUTTON_RIGHT) s.dragging_right = action == GLFW_PRESS;
}

void OnCursor(GLFWwindow* w, double x, double y) {
  State& s = *StateOf(w);
  const float dx = static_cast<float>(x - s.last_x), dy = static_cast<float>(y - s.last_y);
  s.last_x = x;
  s.last_y = y;
  s.dirty = s.dirty || s.dragging_left || s.dragging_right;
  if (s.dragging_left) {
    s.camera = -1;
    s.yaw -= dx * 0.01f;
    s.pitch = std::max(-1.4f, std::min(1.4f, s.pitch + dy * 0.01f));
  } else if (s.dragging_right) {
    s.camera = -1;
    const glm::vec3 right(std::cos(s.yaw), 0, -std::sin(s.yaw));
    s.pan += (-dx * right + glm::vec3(0, dy, 0)) * (0.0015f * s.distance);
  }
}

void OnScroll(GLFWwindow* w, double, double dy) {
  State& s = *StateOf(w);
  s.distance = std::max(0.3f, std::min(30.0f, s.distance * static_cast<float>(std::pow(0.9, dy))));
  s.dirty = true;
}

int Fail(const std::string& m) {
  std::fprintf(stderr, "fvv: %s\n", m.c_str());
  return 1;
}

}  // namespace

const char* PlayerControlsHelp() { return kControls; }

int RunPlayer(const PlayerOptions& o) {
  DecoderPtr dec = MakeDecoder();
  if (!dec || fvv_decoder_open_file(dec.get(), o.input.c_str()) != FVV_OK) {
    return Fail(dec ? fvv_decoder_error(dec.get()) : "cannot create a decoder");
  }
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  if (!glfwInit()) {
    return Fail(
        "fvv play needs a display (no X11 or Wayland session found); use `fvv render` "
        "for headless output");
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(o.width, o.height, "fvv", nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    return Fail("cannot open an OpenGL 3.3 core window");
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  GlApi gl;
  Status s = LoadGlApi(
      [](const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }, &gl);
  fvv_model model;
  fvv_decoder_get_model(dec.get(), &model);
  std::vector<fvv_camera> cameras(info.camera_count);
  std::vector<glm::vec3> centres;
  for (uint32_t c = 0; c < info.camera_count; ++c) {
    fvv_decoder_get_camera(dec.get(), c, &cameras[c]);
    centres.emplace_back(cameras[c].centre[0], cameras[c].centre[1], cameras[c].centre[2]);
  }
  StatusOr<std::unique_ptr<Renderer>> renderer = Internal("no GL");
  if (s.ok()) renderer = Renderer::Create(gl, model, cameras, info.atlas_width, info.atlas_height);
  StatusOr<std::unique_ptr<HudOverlay>> hud = Internal("no GL");
  if (s.ok() && renderer.ok()) hud = HudOverlay::Create(gl);
  if (!s.ok() || !renderer.ok() || !hud.ok()) {
    glfwDestroyWindow(window);
    glfwTerminate();
    return Fail((!s.ok() ? s : !renderer.ok() ? renderer.status() : hud.status()).ToString());
  }
  DecoderFrameSource source(dec.get());
  PlaybackLoop loop(&source, info, centres, o.floor_share);
  loop.all_cameras = o.all_cameras;
  loop.transport().loop = o.loop;
  State state;
  state.t = &loop.transport();
  state.all_cameras = &loop.all_cameras;
  state.exponent = o.exponent;
  state.frames = info.frame_count;
  state.fps = double(info.frame_rate_num) / info.frame_rate_den;
  glfwSetWindowUserPointer(window, &state);
  glfwSetKeyCallback(window, OnKey);
  glfwSetMouseButtonCallback(window, OnButton);
  glfwSetCursorPosCallback(window, OnCursor);
  glfwSetScrollCallback(window, OnScroll);
  std::printf("%s", kControls);

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last = start, title_time = last;
  uint32_t frames_drawn = 0;
  double shown_fps = 0;
  std::vector<std::string> drawn_hud;  // what is on screen: drawn again when it differs
  int drawn_w = 0, drawn_h = 0;
  bool frame_uploaded = false;
  glm::vec3 last_eye(0.0f, 1.0f, 3.5f), last_target(0.0f, 1.0f, 0.0f);  // until the first view
  while (!glfwWindowShouldClose(window)) {
    const auto now = Clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    s = loop.Advance(dt, last_eye, last_target);
    if (!s.ok()) break;
    const fvv_frame* frame = source.frame();
    int fb_w, fb_h;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    const bool last_frame =
        o.seconds > 0 && std::chrono::duration<double>(now - start).count() >= o.seconds;
    std::vector<std::string> hud_lines;
    if (state.hud) {
      hud_lines =
          HudLines(loop, info.frame_count, shown_fps, state,
                   static_cast<int>(source.CamerasTaken()), static_cast<int>(info.camera_count));
    }
    // Draw only when something changed: a still view of a frame already on
    // screen would cost the cores that decoding needs (a software GL renderer
    // takes tens of ms a frame).
    if (!loop.frame_changed() && !state.dirty && hud_lines == drawn_hud && fb_w == drawn_w &&
        fb_h == drawn_h && !last_frame) {
      glfwWaitEventsTimeout(0.004);
      continue;
    }
    state.dirty = false;
    drawn_hud = hud_lines;
    drawn_w = fb_w;
    drawn_h = fb_h;
    const auto r0 = Clock::now();
    if (loop.frame_changed() || !frame_uploaded) {
      s = (*renderer)->SetFrame(*frame);
      if (!s.ok()) break;
      frame_uploaded = true;
    }
    RenderView view;
    view.exponent = state.exponent;
    const glm::vec3 root(frame->bone_world[12], frame->bone_world[13], frame->bone_world[14]);
    const float aspect = fb_h > 0 ? float(fb_w) / float(fb_h) : 1.0f;
    if (state.camera >= 0 && state.camera < static_cast<int>(info.camera_count)) {
      const fvv_camera& c = cameras[state.camera];
      view.eye = centres[state.camera];
      const glm::vec3 forward(c.rotation[6], c.rotation[7], c.rotation[8]);
      const glm::vec3 down(c.rotation[3], c.rotation[4], c.rotation[5]);
      view.view = glm::lookAt(view.eye, view.eye + forward, -down);
      view.projection = glm::perspective(2.0f * std::atan(0.5f * float(c.height) / float(c.fy)),
                                         aspect, 0.05f, 50.0f);
    } else {
      const glm::vec3 target = root + state.pan;
      view.eye = target + state.distance * glm::vec3(std::sin(state.yaw) * std::cos(state.pitch),
                                                     std::sin(state.pitch),
                                                     std::cos(state.yaw) * std::cos(state.pitch));
      view.view = glm::lookAt(view.eye, target, glm::vec3(0, 1, 0));
      view.projection = glm::perspective(glm::radians(40.0f), aspect, 0.05f, 50.0f);
    }
    last_eye = view.eye;
    last_target = state.camera >= 0 && state.camera < static_cast<int>(info.camera_count)
                      ? root
                      : root + state.pan;
    s = (*renderer)->Draw(view, fb_w, fb_h);
    if (!s.ok()) break;
    if (state.hud) {
      s = (*hud)->Draw(hud_lines, fb_w, fb_h, fb_w >= 1600 ? 3 : 2);
      if (!s.ok()) break;
    }
    if (last_frame && !o.screenshot.empty()) {
      Image shot;
      shot.width = static_cast<uint32_t>(fb_w);
      shot.height = static_cast<uint32_t>(fb_h);
      shot.channels = 3;
      s = ReadFramebuffer(gl, fb_w, fb_h, 3, &shot.pixels);
      if (s.ok()) s = WriteImage(o.screenshot, shot);
      if (!s.ok()) break;
    }
    gl.Finish();  // upload and draw time, without the wait for the display's refresh
    loop.FrameDrawn(std::chrono::duration<double, std::milli>(Clock::now() - r0).count());
    glfwSwapBuffers(window);
    ++frames_drawn;
    if (last_frame) glfwSetWindowShouldClose(window, 1);
    const double since = std::chrono::duration<double>(now - title_time).count();
    if (since > 0.5) {
      char title[256];
      const fvv_decode_report& r = frame->report;
      const double budget_ms = r.max_ms_per_gop;
      std::snprintf(
          title, sizeof(title),
          "fvv  frame %u/%u  %.0f fps  decode %.0f ms/GOP (budget %s)  %.0f of %.0f KB "
          "(%.0f%%)  bitplanes Y%u U%u V%u  exp %.1f  x%.2g%s",
          loop.frame_index() + 1, info.frame_count, frames_drawn / since, r.decode_ms,
          budget_ms > 0 ? (std::to_string(int(std::lround(budget_ms))) + " ms").c_str() : "full",
          r.bytes_decoded / 1024.0, r.bytes_available / 1024.0,
          r.bytes_available ? 100.0 * r.bytes_decoded / r.bytes_available : 100.0, r.bitplanes[0],
          r.bitplanes[1], r.bitplanes[2], state.exponent, state.t->speed,
          state.t->playing ? "" : "  [paused]");
      glfwSetWindowTitle(window, title);
      shown_fps = frames_drawn / since;
      title_time = now;
      frames_drawn = 0;
    }
    glfwPollEvents();
  }
  if (o.seconds > 0 && s.ok()) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    const PlaybackStats& st = loop.stats();
    std::printf(
        "played %.1f s: %.1f fps drawn, %.2fx real-time speed, %llu GOPs, decode %.0f ms per "
        "GOP, %.0f%% of texture bytes decoded, %llu stalls, %llu frames without texture\n",
        elapsed, st.frames_drawn / elapsed, st.frames_advanced / (elapsed * state.fps),
        static_cast<unsigned long long>(st.gops), st.gops ? st.decode_ms / st.gops : 0.0,
        st.bytes_available ? 100.0 * st.bytes_decoded / st.bytes_available : 100.0,
        static_cast<unsigned long long>(st.stalls),
        static_cast<unsigned long long>(st.frames_without_texture));
  }
  hud->reset();
  renderer->reset();
  glfwDestroyWindow(window);
  glfwTerminate();
  if (!s.ok()) return Fail(s.ToString());
  return 0;
}

}  // namespace fvv

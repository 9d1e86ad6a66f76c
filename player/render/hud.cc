#include "player/render/hud.h"

#include <algorithm>
#include <cctype>

#include "player/render/shaders.h"

namespace fvv {
namespace {

struct Glyph {
  char c;
  const char* rows[7];  // '#' lit, '.' dark; 5 columns
};

// A classic 5x7 matrix font: digits, capitals and what the HUD prints.
constexpr Glyph kFont[] = {
    {' ', {".....", ".....", ".....", ".....", ".....", ".....", "....."}},
    {'0', {".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."}},
    {'1', {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'2', {".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####"}},
    {'3', {"#####", "...#.", "..#..", "...#.", "....#", "#...#", ".###."}},
    {'4', {"...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#."}},
    {'5', {"#####", "#....", "####.", "....#", "....#", "#...#", ".###."}},
    {'6', {"..##.", ".#...", "#....", "####.", "#...#", "#...#", ".###."}},
    {'7', {"#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#..."}},
    {'8', {".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###."}},
    {'9', {".###.", "#...#", "#...#", ".####", "....#", "...#.", ".##.."}},
    {'A', {".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
    {'B', {"####.", "#...#", "#...#", "####.", "#...#", "#...#", "####."}},
    {'C', {".###.", "#...#", "#....", "#....", "#....", "#...#", ".###."}},
    {'D', {"###..", "#..#.", "#...#", "#...#", "#...#", "#..#.", "###.."}},
    {'E', {"#####", "#....", "#....", "####.", "#....", "#....", "#####"}},
    {'F', {"#####", "#....", "#....", "####.", "#....", "#....", "#...."}},
    {'G', {".###.", "#...#", "#....", "#.###", "#...#", "#...#", ".####"}},
    {'H', {"#...#", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
    {'I', {".###.", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'J', {"..###", "...#.", "...#.", "...#.", "...#.", "#..#.", ".##.."}},
    {'K', {"#...#", "#..#.", "#.#..", "##...", "#.#..", "#..#.", "#...#"}},
    {'L', {"#....", "#....", "#....", "#....", "#....", "#....", "#####"}},
    {'M', {"#...#", "##.##", "#.#.#", "#.#.#", "#...#", "#...#", "#...#"}},
    {'N', {"#...#", "#...#", "##..#", "#.#.#", "#..##", "#...#", "#...#"}},
    {'O', {".###.", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
    {'P', {"####.", "#...#", "#...#", "####.", "#....", "#....", "#...."}},
    {'Q', {".###.", "#...#", "#...#", "#...#", "#.#.#", "#..#.", ".##.#"}},
    {'R', {"####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#"}},
    {'S', {".####", "#....", "#....", ".###.", "....#", "....#", "####."}},
    {'T', {"#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."}},
    {'U', {"#...#", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
    {'V', {"#...#", "#...#", "#...#", "#...#", "#...#", ".#.#.", "..#.."}},
    {'W', {"#...#", "#...#", "#...#", "#.#.#", "#.#.#", "#.#.#", ".#.#."}},
    {'X', {"#...#", "#...#", ".#.#.", "..#..", ".#.#.", "#...#", "#...#"}},
    {'Y', {"#...#", "#...#", ".#.#.", "..#..", "..#..", "..#..", "..#.."}},
    {'Z', {"#####", "....#", "...#.", "..#..", ".#...", "#....", "#####"}},
    {'.', {".....", ".....", ".....", ".....", ".....", ".##..", ".##.."}},
    {',', {".....", ".....", ".....", ".....", ".##..", "..#..", ".#..."}},
    {':', {".....", ".##..", ".##..", ".....", ".##..", ".##..", "....."}},
    {'%', {"##...", "##..#", "...#.", "..#..", ".#...", "#..##", "...##"}},
    {'/', {".....", "....#", "...#.", "..#..", ".#...", "#....", "....."}},
    {'(', {"...#.", "..#..", ".#...", ".#...", ".#...", "..#..", "...#."}},
    {')', {".#...", "..#..", "...#.", "...#.", "...#.", "..#..", ".#..."}},
    {'[', {".###.", ".#...", ".#...", ".#...", ".#...", ".#...", ".###."}},
    {']', {".###.", "...#.", "...#.", "...#.", "...#.", "...#.", ".###."}},
    {'-', {".....", ".....", ".....", "#####", ".....", ".....", "....."}},
    {'+', {".....", "..#..", "..#..", "#####", "..#..", "..#..", "....."}},
    {'=', {".....", ".....", "#####", ".....", "#####", ".....", "....."}},
    {'|', {"..#..", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."}},
    {'?', {".###.", "#...#", "....#", "...#.", "..#..", ".....", "..#.."}},
};

const Glyph& GlyphOf(char c) {
  const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const Glyph& g : kFont) {
    if (g.c == upper) return g;
  }
  return kFont[sizeof(kFont) / sizeof(kFont[0]) - 1];  // '?'
}

const char* const kVertex = shaders::kHudVert;

const char* const kFragment = shaders::kHudFrag;

void AddQuad(float x0, float y0, float x1, float y1, std::vector<float>* v) {
  const float q[12] = {x0, y0, x1, y0, x1, y1, x0, y0, x1, y1, x0, y1};
  v->insert(v->end(), q, q + 12);
}

}  // namespace

StatusOr<std::unique_ptr<HudOverlay>> HudOverlay::Create(const GlApi& gl) {
  std::unique_ptr<HudOverlay> h(new HudOverlay(gl));
  FVV_ASSIGN_OR_RETURN(h->program_, BuildProgram(gl, kVertex, kFragment, "HUD shader"));
  h->colour_location_ = gl.GetUniformLocation(h->program_, "u_colour");
  h->viewport_location_ = gl.GetUniformLocation(h->program_, "u_viewport");
  gl.GenVertexArrays(1, &h->vao_);
  gl.GenBuffers(1, &h->vbo_);
  gl.BindVertexArray(h->vao_);
  gl.BindBuffer(GL_ARRAY_BUFFER, h->vbo_);
  gl.EnableVertexAttribArray(0);
  gl.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  gl.BindVertexArray(0);
  return h;
}

HudOverlay::~HudOverlay() {
  if (vbo_) gl_.DeleteBuffers(1, &vbo_);
  if (vao_) gl_.DeleteVertexArrays(1, &vao_);
  if (program_) gl_.DeleteProgram(program_);
}

int HudOverlay::LitPixels(const std::string& text) {
  int lit = 0;
  for (char c : text) {
    for (const char* row : GlyphOf(c).rows) lit += static_cast<int>(std::count(row, row + 5, '#'));
  }
  return lit;
}

void HudOverlay::PanelSize(const std::vector<std::string>& lines, int scale, int* width,
                           int* height) {
  size_t longest = 0;
  for (const std::string& l : lines) longest = std::max(longest, l.size());
  *width = (2 * kMargin + static_cast<int>(longest) * kAdvance - 1) * scale;
  *height = (2 * kMargin + static_cast<int>(lines.size()) * kLineHeight - 2) * scale;
}

Status HudOverlay::Draw(const std::vector<std::string>& lines, int width, int height, int scale) {
  if (lines.empty()) return Status::Ok();
  if (scale < 1 || width < 1 || height < 1) return InvalidArgument("HUD: bad size or scale");
  std::vector<float> panel, text;
  int panel_w, panel_h;
  PanelSize(lines, scale, &panel_w, &panel_h);
  AddQuad(0, 0, static_cast<float>(panel_w), static_cast<float>(panel_h), &panel);
  for (size_t l = 0; l < lines.size(); ++l) {
    for (size_t i = 0; i < lines[l].size(); ++i) {
      const Glyph& g = GlyphOf(lines[l][i]);
      const int x0 = kMargin + static_cast<int>(i) * kAdvance;
      const int y0 = kMargin + static_cast<int>(l) * kLineHeight;
      for (int y = 0; y < kGlyphHeight; ++y) {
        for (int x = 0; x < kGlyphWidth; ++x) {
          if (g.rows[y][x] != '#') continue;
          AddQuad(static_cast<float>((x0 + x) * scale), static_cast<float>((y0 + y) * scale),
                  static_cast<float>((x0 + x + 1) * scale),
                  static_cast<float>((y0 + y + 1) * scale), &text);
        }
      }
    }
  }
  gl_.Viewport(0, 0, width, height);
  gl_.Disable(GL_DEPTH_TEST);
  gl_.UseProgram(program_);
  gl_.Uniform2f(viewport_location_, static_cast<float>(width), static_cast<float>(height));
  gl_.BindVertexArray(vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  const float panel_colour[3] = {0.05f, 0.05f, 0.08f}, text_colour[3] = {0.35f, 1.0f, 0.45f};
  for (int pass = 0; pass < 2; ++pass) {
    const std::vector<float>& v = pass == 0 ? panel : text;
    if (v.empty()) continue;
    gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(v.size() * sizeof(float)), v.data(),
                   GL_STREAM_DRAW);
    gl_.Uniform3fv(colour_location_, 1, pass == 0 ? panel_colour : text_colour);
    gl_.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(v.size() / 2));
  }
  gl_.BindVertexArray(0);
  gl_.Enable(GL_DEPTH_TEST);
  const GLenum error = gl_.GetError();
  if (error != GL_NO_ERROR) return Internal("HUD: GL error " + std::to_string(error));
  return Status::Ok();
}

}  // namespace fvv

// Blits made once on tiny images, ahead of the switches that will need their kind.
//
// Drivers build the shaders they blit with at the first blit of each kind, not before: on
// llvmpipe tens of milliseconds of LLVM on the calling thread for each, a kind being the two
// formats, the filter and whether the source's sides are powers of two (its sampler state keeps
// that). A level switch is the first time the scaler stretches a target, so without this the
// switch's frame pays for those builds in the middle of the run (on the demo 1.8-4x the frames
// around it, where later switches to the same scales cost nothing). Here each kind a switch can
// bring is blitted once when the scaler first meets it: an app framebuffer when it is first
// drawn into (its images' rescales), the window at its first swap (the stand-in's present).
// Only where the configuration can change at run time (a fixed one pays its blits at start),
// and not with GLBUDGET_WARM_BLITS=0.
#include <algorithm>
#include <vector>

#include "apply_gl.hpp"
#include "options.hpp"
#include "render_targets.hpp"
#include "target_images.hpp"

namespace glbudget {

using namespace target_images;

namespace {

bool power_of_two(GLsizei n) { return n > 0 && (n & (n - 1)) == 0; }

// A side of a tiny image with the power-of-two-ness of `pot`.
GLsizei tiny_side(bool pot) { return pot ? 4 : 3; }

// Every scale `scale_of(configuration)` gives over all configurations. The scale a
// configuration gives a target is the smallest of its levels' scales that reach it, so the
// configurations with one pass off its best level already give them all.
template <typename ScaleOf>
std::vector<double> possible_scales(ScaleOf&& scale_of) {
  const manifest::Manifest& m = active_manifest();
  std::vector<double> scales{1.0};
  Levels config;
  config.count = static_cast<int>(std::min<size_t>(m.passes.size(), kMaxPasses));
  for (int q = 0; q < config.count; ++q) {
    const size_t levels = m.passes[static_cast<size_t>(q)].levels.size();
    for (size_t l = 1; l < levels && l < 128; ++l) {
      config.level[q] = static_cast<int8_t>(l);
      const double s = scale_of(config);
      if (std::find(scales.begin(), scales.end(), s) == scales.end()) scales.push_back(s);
    }
    config.level[q] = 0;
  }
  return scales;
}

}  // namespace

void TargetScaler::warm_rescales(GLuint name, const Framebuffer& f) {
  if (!blits() || !options().warm_blits || !configuration_may_change()) return;
  const std::vector<double> scales = possible_scales([&](const Levels& c) { return scale_for(name, f, c); });
  if (scales.size() < 2) return;
  for (const Attachment& a : f.attachments) {
    const auto& images = a.renderbuffer ? renderbuffers_ : textures_;
    const auto it = images.find(a.name);
    if (it == images.end() || it->second.app_size.empty()) continue;
    const Image& image = it->second;
    // A rescale carries no multisampled image over; layers and faces are left cold.
    if (image.samples != 0 || (!image.renderbuffer && image.kind != GL_TEXTURE_2D)) continue;
    for (double s : scales)
      warm_blit(image, power_of_two(scaled(image.app_size[0][0], s)), power_of_two(scaled(image.app_size[0][1], s)));
  }
}

// rescale()'s two blits: the image at one size stretched into a copy at another, and the copy
// back at its own size.
void TargetScaler::warm_blit(const Image& image, bool pot_width, bool pot_height) {
  const std::array<GLint, 7> kind{image.renderbuffer,
                                  static_cast<GLint>(image.kind),
                                  image.internal_format,
                                  static_cast<GLint>(image.format),
                                  static_cast<GLint>(image.type),
                                  pot_width,
                                  pot_height};
  if (!warmed_.insert(kind).second) return;
  // Only single-sampled 2D images get here, so `image`'s own kind and samples are the tiny ones'.
  const ApplyGl& g = agl();
  SavedBindings saved(GL_TEXTURE_2D);
  const GLsizei w = tiny_side(pot_width), h = tiny_side(pot_height);
  const GLbitfield mask = buffer_bits(image.internal_format);
  GLuint objects[3] = {0, 0, 0}, fbo[2] = {0, 0};
  if (image.renderbuffer)
    g.GenRenderbuffers(3, objects);
  else
    g.GenTextures(3, objects);
  const GLsizei sizes[3][2] = {{w, h}, {2, 2}, {w, h}};
  for (int i = 0; i < 3; ++i) allocate_like(image, objects[i], sizes[i][0], sizes[i][1], 0);
  g.GenFramebuffers(2, fbo);
  attach_like(image, GL_READ_FRAMEBUFFER, fbo[0], objects[0], 0);
  attach_like(image, GL_DRAW_FRAMEBUFFER, fbo[1], objects[1], 0);
  g.BlitFramebuffer(0, 0, w, h, 0, 0, 2, 2, mask, stretch_filter(image.internal_format, image.format));
  attach_like(image, GL_DRAW_FRAMEBUFFER, fbo[1], objects[2], 0);
  g.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, mask, GL_NEAREST);
  g.DeleteFramebuffers(2, fbo);
  if (image.renderbuffer)
    g.DeleteRenderbuffers(3, objects);
  else
    g.DeleteTextures(3, objects);
}

// The present stretches the stand-in (single-sampled, of the window's colour format) over the
// back buffer. Its kind is warmed on the back buffer itself, over a 2x2 corner whose pixels
// are kept aside first and put back after, so the frame the app drew reaches the screen whole.
void TargetScaler::warm_present() {
  if (!blits() || !options().warm_blits || window_unscalable_ || window_width_ < 2 || window_height_ < 2 ||
      !configuration_may_change())
    return;
  if (warmed_present_.count({-1, -1})) return;  // nothing (more) to warm on this window
  check_window();
  const std::vector<double> scales = possible_scales([&](const Levels& c) { return window_scale_for(c); });
  std::vector<std::array<int, 2>> wanted;
  for (double s : scales) {
    if (s == 1.0) continue;
    const std::array<int, 2> k{power_of_two(scaled(window_width_, s)), power_of_two(scaled(window_height_, s))};
    if (!warmed_present_.count(k) && std::find(wanted.begin(), wanted.end(), k) == wanted.end()) wanted.push_back(k);
  }
  // A multisampled window's present goes through copies of its own; it stays cold.
  if (wanted.empty() || window_.samples > 0) {
    warmed_present_.insert({-1, -1});
    return;
  }
  const ApplyGl& g = agl();
  SavedBindings saved(GL_TEXTURE_2D);
  GLint read_buffer = GL_BACK, draw_buffer = GL_BACK;
  g.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  g.GetIntegerv(GL_READ_BUFFER, &read_buffer);
  g.GetIntegerv(GL_DRAW_BUFFER0, &draw_buffer);
  // A double-buffered window read and drawn in its back buffer, as apps leave it: the corner is
  // kept from and put back into the buffer the present draws into, with no glReadBuffer of the
  // shim's (others are rare and stay cold).
  if ((draw_buffer != GL_BACK && draw_buffer != GL_BACK_LEFT) || read_buffer != draw_buffer) {
    warmed_present_.insert({-1, -1});
    return;
  }
  GLuint images[2] = {0, 0}, fbo = 0;
  g.GenRenderbuffers(2, images);
  g.GenFramebuffers(1, &fbo);
  g.BindRenderbuffer(GL_RENDERBUFFER, images[0]);
  g.RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, window_.color_format, 2, 2);
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
  g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, images[0]);
  g.BlitFramebuffer(0, 0, 2, 2, 0, 0, 2, 2, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  g.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  for (const std::array<int, 2>& k : wanted) {
    const GLsizei w = tiny_side(k[0] != 0), h = tiny_side(k[1] != 0);
    g.BindRenderbuffer(GL_RENDERBUFFER, images[1]);
    g.RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, window_.color_format, w, h);
    g.FramebufferRenderbuffer(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, images[1]);
    g.BlitFramebuffer(0, 0, w, h, 0, 0, 2, 2, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    warmed_present_.insert(k);
  }
  g.FramebufferRenderbuffer(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, images[0]);
  g.BlitFramebuffer(0, 0, 2, 2, 0, 0, 2, 2, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  g.DeleteFramebuffers(1, &fbo);
  g.DeleteRenderbuffers(2, images);
}

}  // namespace glbudget

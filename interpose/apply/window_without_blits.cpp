// The window's stand-in in a context with framebuffer objects but no blits (OpenGL ES 2.0):
// one framebuffer binding for reading and drawing, no multisampled renderbuffers, no sized
// colour formats. The stand-in's colour is a texture, drawn into the back buffer at each swap
// and into a window-sized copy for reads (glReadPixels, glCopyTex* of the window).
#include <algorithm>
#include <cstdio>
#include <string>

#include "apply_gl.hpp"
#include "hook_table.hpp"
#include "messages.hpp"
#include "render_targets.hpp"

namespace glbudget {

namespace {
void store_renderbuffer(GLenum format, int width, int height) {
  static const auto storage = reinterpret_cast<PFNGLRENDERBUFFERSTORAGEPROC>(resolve_gl("glRenderbufferStorage"));
  storage(GL_RENDERBUFFER, format, width, height);
}

GLenum framebuffer_status() {
  static const auto check = reinterpret_cast<PFNGLCHECKFRAMEBUFFERSTATUSPROC>(resolve_gl("glCheckFramebufferStatus"));
  return check(GL_FRAMEBUFFER);
}
}  // namespace

void TargetScaler::check_window_without_blits() {
  const ApplyGl& g = agl();
  // Asked of the window itself: GLES 2.0 answers attachment questions of framebuffer objects only.
  GLint bound = 0, samples = 0, depth_bits = 0, stencil_bits = 0;
  g.GetIntegerv(GL_FRAMEBUFFER_BINDING, &bound);
  if (bound) g.BindFramebuffer(GL_FRAMEBUFFER, 0);
  g.GetIntegerv(GL_SAMPLES, &samples);
  g.GetIntegerv(GL_DEPTH_BITS, &depth_bits);
  g.GetIntegerv(GL_STENCIL_BITS, &stencil_bits);
  if (bound) g.BindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(bound));
  window_.samples = samples > 0 ? samples : 0;
  window_.has_depth = depth_bits > 0 || stencil_bits > 0;
  window_.depth_stencil = {std::max(0, depth_bits), std::max(0, stencil_bits), false};
  // Where the window has stencil: a depth-stencil image, else one of each.
  const bool packed = stencil_bits > 0 && has_extension(caps_, "GL_OES_packed_depth_stencil");
  window_.depth_format = packed                                                      ? GL_DEPTH24_STENCIL8
                         : depth_bits > 16 && has_extension(caps_, "GL_OES_depth24") ? GL_DEPTH_COMPONENT24
                         : depth_bits > 0                                            ? GL_DEPTH_COMPONENT16
                                                                                     : GLenum{GL_NONE};
  window_.separate_stencil = stencil_bits > 0 && !packed;
  window_.color_format = GL_RGBA;
}

void TargetScaler::make_drawable_images(GLuint fbo, GLuint* color, GLuint* depth, GLuint* stencil, int width,
                                        int height, bool fresh) {
  const ApplyGl& g = agl();
  GLint texture = 0, renderbuffer = 0, framebuffer = 0, active = GL_TEXTURE0;
  g.GetIntegerv(GL_ACTIVE_TEXTURE, &active);
  g.ActiveTexture(GL_TEXTURE0);
  g.GetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
  g.GetIntegerv(GL_RENDERBUFFER_BINDING, &renderbuffer);
  g.GetIntegerv(GL_FRAMEBUFFER_BINDING, &framebuffer);
  if (fresh) g.GenTextures(1, color);
  g.BindTexture(GL_TEXTURE_2D, *color);
  g.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  if (fresh) {
    // Stretched to the window by the copy's draw: filtered as a blit with GL_LINEAR would be;
    // a texture of any size is complete with no mipmaps and clamped edges.
    g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  const bool with_depth = depth && window_.depth_format != GL_NONE;
  const bool with_stencil = stencil && window_.separate_stencil;
  if (fresh && with_depth) g.GenRenderbuffers(1, depth);
  if (fresh && with_stencil) g.GenRenderbuffers(1, stencil);
  if (with_depth) {
    g.BindRenderbuffer(GL_RENDERBUFFER, *depth);
    store_renderbuffer(window_.depth_format, width, height);
  }
  if (with_stencil) {
    g.BindRenderbuffer(GL_RENDERBUFFER, *stencil);
    store_renderbuffer(GL_STENCIL_INDEX8, width, height);
  }
  if (fresh) {
    g.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    g.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *color, 0);
    if (with_depth) {
      g.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, *depth);
      if (window_.depth_format == GL_DEPTH24_STENCIL8)
        g.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_RENDERBUFFER, *depth);
    }
    if (with_stencil) g.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_RENDERBUFFER, *stencil);
  }
  g.BindTexture(GL_TEXTURE_2D, static_cast<GLuint>(texture));
  g.ActiveTexture(static_cast<GLenum>(active));
  g.BindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(renderbuffer));
  g.BindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(framebuffer));
}

void TargetScaler::update_window_without_blits(int width, int height) {
  const ApplyGl& g = agl();
  const bool fresh = !window_.fbo;
  if (fresh && !draw_copy_->ready()) {  // nothing could show the stand-in: said by DrawCopy
    window_unscalable_ = true;
    return;
  }
  if (fresh) {
    g.GenFramebuffers(1, &window_.fbo);
    window_.color_texture = true;
  }
  window_.width = width;
  window_.height = height;
  make_drawable_images(window_.fbo, &window_.color, &window_.depth, &window_.stencil, width, height, fresh);
  if (fresh) {
    GLint framebuffer = 0;
    g.GetIntegerv(GL_FRAMEBUFFER_BINDING, &framebuffer);
    g.BindFramebuffer(GL_FRAMEBUFFER, window_.fbo);
    const GLenum status = framebuffer_status();
    g.BindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(framebuffer));
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      say_once(
          "window-incomplete", "the driver does not take the window's stand-in (framebuffer status 0x" + [&] {
            char hex[16];
            snprintf(hex, sizeof hex, "%x", status);
            return std::string(hex);
          }() + "): the window is not scaled");
      release_window_without_blits();
      window_unscalable_ = true;
      return;
    }
  }
  if (draw_fbo_ == 0) g.BindFramebuffer(GL_FRAMEBUFFER, window_.fbo);
  delete_image_set(window_.copy);  // follows the window's size
  apply_viewport();
}

void TargetScaler::release_window_without_blits() {
  const ApplyGl& g = agl();
  if (draw_fbo_ == 0) g.BindFramebuffer(GL_FRAMEBUFFER, 0);
  g.DeleteFramebuffers(1, &window_.fbo);
  g.DeleteTextures(1, &window_.color);
  if (window_.depth) g.DeleteRenderbuffers(1, &window_.depth);
  if (window_.stencil) g.DeleteRenderbuffers(1, &window_.stencil);
  window_.fbo = window_.color = window_.depth = window_.stencil = 0;
  window_.width = window_.height = 0;
  delete_image_set(window_.copy);
  apply_viewport();
}

void TargetScaler::present_without_blits() { draw_copy_->copy(window_.color, 0, window_width_, window_height_); }

void TargetScaler::bind_window_copy_without_blits() {
  ImageSet& copy = window_.copy;
  if (!copy.fbo || copy.width != window_width_ || copy.height != window_height_) {
    const bool fresh = !copy.fbo;
    if (fresh) {
      agl().GenFramebuffers(1, &copy.fbo);
      copy.color_texture = true;
    }
    copy.width = window_width_;
    copy.height = window_height_;
    // Colour alone: GLES 2.0 reads and copies nothing else out of a framebuffer.
    make_drawable_images(copy.fbo, &copy.color, nullptr, nullptr, copy.width, copy.height, fresh);
  }
  draw_copy_->copy(window_.color, copy.fbo, copy.width, copy.height);
  agl().BindFramebuffer(GL_FRAMEBUFFER, copy.fbo);
}

}  // namespace glbudget

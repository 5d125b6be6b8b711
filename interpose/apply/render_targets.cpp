#include "render_targets.hpp"
#include "messages.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <set>
#include <string>

#include "apply_gl.hpp"
#include "target_images.hpp"

namespace glbudget {

using namespace target_images;

namespace {

// The format and type glTexImage2D takes with no data for a sized format a framebuffer can
// hold; false for others (compressed, unsized, luminance), which keep their immutable storage.
bool null_upload(GLenum internal_format, GLenum* format, GLenum* type) {
  struct Row {
    GLenum internal, format, type;
  };
  static constexpr Row kRows[] = {
      {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE},
      {GL_SRGB8_ALPHA8, GL_RGBA, GL_UNSIGNED_BYTE},
      {GL_RGB8, GL_RGB, GL_UNSIGNED_BYTE},
      {GL_RG8, GL_RG, GL_UNSIGNED_BYTE},
      {GL_R8, GL_RED, GL_UNSIGNED_BYTE},
      {GL_RGB565, GL_RGB, GL_UNSIGNED_SHORT_5_6_5},
      {GL_RGBA4, GL_RGBA, GL_UNSIGNED_SHORT_4_4_4_4},
      {GL_RGB5_A1, GL_RGBA, GL_UNSIGNED_SHORT_5_5_5_1},
      {GL_RGB10_A2, GL_RGBA, GL_UNSIGNED_INT_2_10_10_10_REV},
      {GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT},
      {GL_RGB16F, GL_RGB, GL_HALF_FLOAT},
      {GL_RG16F, GL_RG, GL_HALF_FLOAT},
      {GL_R16F, GL_RED, GL_HALF_FLOAT},
      {GL_RGBA32F, GL_RGBA, GL_FLOAT},
      {GL_RGB32F, GL_RGB, GL_FLOAT},
      {GL_RG32F, GL_RG, GL_FLOAT},
      {GL_R32F, GL_RED, GL_FLOAT},
      {GL_R11F_G11F_B10F, GL_RGB, GL_UNSIGNED_INT_10F_11F_11F_REV},
      {GL_RGBA16, GL_RGBA, GL_UNSIGNED_SHORT},
      {GL_RGB16, GL_RGB, GL_UNSIGNED_SHORT},
      {GL_RG16, GL_RG, GL_UNSIGNED_SHORT},
      {GL_R16, GL_RED, GL_UNSIGNED_SHORT},
      {GL_RGBA16_SNORM, GL_RGBA, GL_SHORT},
      {GL_RG16_SNORM, GL_RG, GL_SHORT},
      {GL_R16_SNORM, GL_RED, GL_SHORT},
      {GL_RGBA8_SNORM, GL_RGBA, GL_BYTE},
      {GL_RG8_SNORM, GL_RG, GL_BYTE},
      {GL_R8_SNORM, GL_RED, GL_BYTE},
      {GL_RGB10_A2UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT_2_10_10_10_REV},
      {GL_RGBA8UI, GL_RGBA_INTEGER, GL_UNSIGNED_BYTE},
      {GL_RGBA8I, GL_RGBA_INTEGER, GL_BYTE},
      {GL_RGBA16UI, GL_RGBA_INTEGER, GL_UNSIGNED_SHORT},
      {GL_RGBA16I, GL_RGBA_INTEGER, GL_SHORT},
      {GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT},
      {GL_RGBA32I, GL_RGBA_INTEGER, GL_INT},
      {GL_RG8UI, GL_RG_INTEGER, GL_UNSIGNED_BYTE},
      {GL_RG16UI, GL_RG_INTEGER, GL_UNSIGNED_SHORT},
      {GL_RG32UI, GL_RG_INTEGER, GL_UNSIGNED_INT},
      {GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE},
      {GL_R16UI, GL_RED_INTEGER, GL_UNSIGNED_SHORT},
      {GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT},
      {GL_R32I, GL_RED_INTEGER, GL_INT},
      {GL_RG8I, GL_RG_INTEGER, GL_BYTE},
      {GL_RG16I, GL_RG_INTEGER, GL_SHORT},
      {GL_RG32I, GL_RG_INTEGER, GL_INT},
      {GL_R8I, GL_RED_INTEGER, GL_BYTE},
      {GL_R16I, GL_RED_INTEGER, GL_SHORT},
      {GL_DEPTH_COMPONENT16, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT},
      {GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT},
      {GL_DEPTH_COMPONENT32, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT},
      {GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT},
      {GL_DEPTH24_STENCIL8, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8},
      {GL_DEPTH32F_STENCIL8, GL_DEPTH_STENCIL, GL_FLOAT_32_UNSIGNED_INT_24_8_REV},
  };
  for (const Row& r : kRows)
    if (r.internal == internal_format) {
      *format = r.format;
      *type = r.type;
      return true;
    }
  return false;
}

// A format of the table above that OpenGL ES 3 takes without an extension (16-bit normalised
// ones need EXT_texture_norm16; 32-bit integer depth is desktop only).
bool in_gles(GLenum internal_format) {
  switch (internal_format) {
    case GL_RGBA16:
    case GL_RGB16:
    case GL_RG16:
    case GL_R16:
    case GL_RGBA16_SNORM:
    case GL_RG16_SNORM:
    case GL_R16_SNORM:
    case GL_DEPTH_COMPONENT32:
      return false;
    default:
      return true;
  }
}

}  // namespace

}  // namespace glbudget

#include "hook_table.hpp"

namespace glbudget {

target_images::SavedBindings::SavedBindings(GLenum texture_kind) : kind(texture_kind) {
  const ApplyGl& g = agl();
  g.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  g.GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
  g.GetIntegerv(TargetScaler::binding_of(kind), &texture);
  g.GetIntegerv(GL_RENDERBUFFER_BINDING, &renderbuffer);
  g.GetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack);
  scissor = g.IsEnabled(GL_SCISSOR_TEST);
  if (unpack) reinterpret_cast<PFNGLBINDBUFFERPROC>(bind_buffer())(GL_PIXEL_UNPACK_BUFFER, 0);
  if (scissor) g.Disable(GL_SCISSOR_TEST);  // a blit is clipped by the scissor box
}

target_images::SavedBindings::~SavedBindings() {
  const ApplyGl& g = agl();
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
  g.BindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read));
  g.BindTexture(kind, static_cast<GLuint>(texture));
  g.BindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(renderbuffer));
  if (unpack) reinterpret_cast<PFNGLBINDBUFFERPROC>(bind_buffer())(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(unpack));
  if (scissor) g.Enable(GL_SCISSOR_TEST);
}

void* target_images::SavedBindings::bind_buffer() {
  static void* fn = resolve_gl("glBindBuffer");
  return fn;
}

GLsizei TargetScaler::Image::stored_width() const { return app_size.empty() ? 0 : scaled(app_size[0][0], scale); }
GLsizei TargetScaler::Image::stored_height() const { return app_size.empty() ? 0 : scaled(app_size[0][1], scale); }

std::array<GLsizei, 2> TargetScaler::Image::stored_level_size(size_t level) const {
  const auto& app = app_size[level];
  if (level == 0 || scale == 1.0) return {scaled(app[0], scale), scaled(app[1], scale)};
  const auto& base = app_size[0];
  const bool chain = level < 31 && app[0] == std::max(1, base[0] >> level) && app[1] == std::max(1, base[1] >> level);
  if (!chain) return {scaled(app[0], scale), scaled(app[1], scale)};
  return {std::max(1, stored_width() >> level), std::max(1, stored_height() >> level)};
}

TargetScaler::TargetScaler(const GlCaps& caps) : caps_(caps) {
  const ApplyGl& g = agl();
  g.GetIntegerv(GL_VIEWPORT, viewport_.data());
  g.GetIntegerv(GL_SCISSOR_BOX, scissor_.data());
  // GL sets the first viewport to the window's size: the size until the window system says.
  window_width_ = viewport_[2];
  window_height_ = viewport_[3];
  GLint fbo = 0;
  g.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fbo);  // GL_FRAMEBUFFER_BINDING, the same enum
  draw_fbo_ = static_cast<GLuint>(fbo);
  if (!blits()) {  // one binding for reading and drawing: GL_READ_FRAMEBUFFER_BINDING is an error
    read_fbo_ = draw_fbo_;
    draw_copy_ = std::make_unique<DrawCopy>(caps_.gles);
    return;
  }
  g.GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &fbo);
  read_fbo_ = static_cast<GLuint>(fbo);
}

void TargetScaler::set_configuration(const Levels& config) {
  if (config == config_) return;
  config_ = config;
  // At a swap: a framebuffer the last frame cleared whole before drawing into it will be
  // cleared again before it is read, so its contents need not be carried over.
  for (auto& [name, f] : framebuffers_) ensure_scale(name, f, !cleared_before_drawn(f));
  update_window();
  apply_viewport();
}

double TargetScaler::window_scale_for(const Levels& config) const {
  const manifest::Manifest& m = active_manifest();
  double s = 1.0;
  for (size_t q = 0; q < m.passes.size(); ++q) {
    const int l = config[static_cast<int>(q)];
    if (l < 0 || static_cast<size_t>(l) >= m.passes[q].levels.size()) continue;
    const manifest::Level& level = m.passes[q].levels[static_cast<size_t>(l)];
    for (const manifest::Target& t : level.targets)
      if (t.kind == manifest::Target::Kind::default_framebuffer) s = std::min(s, level.scale);
  }
  return s;
}

GLenum TargetScaler::window_buffer(GLenum buffer) {
  switch (buffer) {
    case GL_BACK:
    case GL_FRONT:
    case GL_BACK_LEFT:
    case GL_FRONT_LEFT:
    case GL_LEFT:
    case GL_FRONT_AND_BACK:
      return GL_COLOR_ATTACHMENT0;
    default:
      return buffer;
  }
}

void TargetScaler::set_window_size(int width, int height) {
  if (width <= 0 || height <= 0 || (width == window_width_ && height == window_height_)) return;
  window_width_ = width;
  window_height_ = height;
  if (window_.fbo) update_window();
}

void TargetScaler::check_window() {
  if (window_.checked) return;
  // What the window is made of, asked of the real default framebuffer.
  window_.checked = true;
  if (!blits()) return check_window_without_blits();
  const ApplyGl& g = agl();
  GLint draw = 0, samples = 0, depth = GL_NONE, stencil = GL_NONE, encoding = GL_LINEAR;
  g.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  g.GetIntegerv(GL_SAMPLES, &samples);
  // The object type is the one parameter an absent buffer may be asked (any other is a
  // GL_INVALID_OPERATION the app would read from glGetError).
  g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &depth);
  g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_STENCIL, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE,
                                        &stencil);
  g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, caps_.gles ? GL_BACK : GL_BACK_LEFT,
                                        GL_FRAMEBUFFER_ATTACHMENT_COLOR_ENCODING, &encoding);
  DepthStencil& ds = window_.depth_stencil;
  GLint component = GL_NONE;
  if (depth != GL_NONE) {
    g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE,
                                          &ds.depth_bits);
    g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_DEPTH, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE,
                                          &component);
  }
  if (stencil != GL_NONE)
    g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, GL_STENCIL, GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE,
                                          &ds.stencil_bits);
  ds.floating_depth = component == GL_FLOAT;
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
  window_.samples = std::max(0, samples);
  window_.has_depth = depth != GL_NONE || stencil != GL_NONE;
  window_.color_format = encoding == GL_SRGB ? GL_SRGB8_ALPHA8 : GL_RGBA8;
}

int TargetScaler::window_samples() {
  check_window();
  return window_.samples;
}

const TargetScaler::DepthStencil& TargetScaler::window_depth_stencil() {
  check_window();
  return window_.depth_stencil;
}

void TargetScaler::update_window() {
  const ApplyGl& g = agl();
  const double s = wanted_window_scale();
  if (s == 1.0 || window_width_ <= 0 || window_height_ <= 0 || window_unscalable_) {
    release_window();
    return;
  }
  check_window();
  // A multisampled stand-in is resolved, then stretched, then written into the window, whose
  // samples then all take the pixel's value: GLES has no blit into a multisampled window.
  if (window_.samples > 0 && caps_.gles) {
    say_once("multisampled-window", "the window is multisampled (GLES): its resolution is not scaled");
    return;
  }
  const int w = scaled(window_width_, s), h = scaled(window_height_, s);
  if (window_.fbo && w == window_.width && h == window_.height) return;
  if (!blits()) return update_window_without_blits(w, h);
  GLint renderbuffer = 0, draw = 0, read = 0;
  g.GetIntegerv(GL_RENDERBUFFER_BINDING, &renderbuffer);
  g.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  g.GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
  const bool fresh = !window_.fbo;
  if (fresh) {
    g.GenFramebuffers(1, &window_.fbo);
    g.GenRenderbuffers(1, &window_.color);
    if (window_.has_depth) g.GenRenderbuffers(1, &window_.depth);
  }
  window_.width = w;
  window_.height = h;
  g.BindRenderbuffer(GL_RENDERBUFFER, window_.color);
  g.RenderbufferStorageMultisample(GL_RENDERBUFFER, window_.samples, window_.color_format, w, h);
  if (window_.depth) {
    g.BindRenderbuffer(GL_RENDERBUFFER, window_.depth);
    g.RenderbufferStorageMultisample(GL_RENDERBUFFER, window_.samples, GL_DEPTH24_STENCIL8, w, h);
  }
  g.BindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(renderbuffer));
  if (fresh) {
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, window_.fbo);
    g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, window_.color);
    if (window_.depth)
      g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, window_.depth);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
  }
  // The stand-in takes the window's place in whichever binding the app has at 0.
  if (draw_fbo_ == 0) g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, window_.fbo);
  if (read_fbo_ == 0) g.BindFramebuffer(GL_READ_FRAMEBUFFER, window_.fbo);
  // The read copy follows the window's size, the resolve the stand-in's.
  delete_image_set(window_.copy);
  delete_image_set(window_.resolve);
  apply_viewport();
}

void TargetScaler::delete_image_set(ImageSet& set) {
  if (!set.fbo) return;
  const ApplyGl& g = agl();
  g.DeleteFramebuffers(1, &set.fbo);
  if (set.color_texture)
    g.DeleteTextures(1, &set.color);
  else
    g.DeleteRenderbuffers(1, &set.color);
  if (set.depth) g.DeleteRenderbuffers(1, &set.depth);
  set = ImageSet{};
}

void TargetScaler::ensure_image_set(ImageSet& set, int width, int height) {
  if (set.fbo && set.width == width && set.height == height) return;
  delete_image_set(set);
  const ApplyGl& g = agl();
  GLint renderbuffer = 0, draw = 0;
  g.GetIntegerv(GL_RENDERBUFFER_BINDING, &renderbuffer);
  g.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  set.width = width;
  set.height = height;
  g.GenFramebuffers(1, &set.fbo);
  g.GenRenderbuffers(1, &set.color);
  g.BindRenderbuffer(GL_RENDERBUFFER, set.color);
  g.RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, window_.color_format, width, height);
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, set.fbo);
  g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, set.color);
  if (window_.has_depth) {
    g.GenRenderbuffers(1, &set.depth);
    g.BindRenderbuffer(GL_RENDERBUFFER, set.depth);
    g.RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, GL_DEPTH24_STENCIL8, width, height);
    g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, set.depth);
  }
  g.BindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(renderbuffer));
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
}

void TargetScaler::release_window() {
  if (!window_.fbo) return;
  if (!blits()) return release_window_without_blits();
  const ApplyGl& g = agl();
  if (draw_fbo_ == 0) g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  if (read_fbo_ == 0) g.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  g.DeleteFramebuffers(1, &window_.fbo);
  g.DeleteRenderbuffers(1, &window_.color);
  if (window_.depth) g.DeleteRenderbuffers(1, &window_.depth);
  window_.fbo = window_.color = window_.depth = 0;
  window_.width = window_.height = 0;
  delete_image_set(window_.copy);
  delete_image_set(window_.resolve);
  apply_viewport();
}

namespace {
// Bindings and switches a blit of ours changes, restored when it is done.
struct BlitState {
  GLint draw = 0, read = 0;
  bool scissor = false, discard = false;
  BlitState() {
    const ApplyGl& g = agl();
    g.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
    g.GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
    scissor = g.IsEnabled(GL_SCISSOR_TEST);
    discard = g.IsEnabled(GL_RASTERIZER_DISCARD);
    if (scissor) g.Disable(GL_SCISSOR_TEST);  // a leftover scissor clips blits
    if (discard) g.Disable(GL_RASTERIZER_DISCARD);
  }
  ~BlitState() {
    const ApplyGl& g = agl();
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
    g.BindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read));
    if (scissor) g.Enable(GL_SCISSOR_TEST);
    if (discard) g.Enable(GL_RASTERIZER_DISCARD);
  }
};

// Blits the whole colour (linear) and depth-stencil (nearest) of `from` over `to`.
void blit_whole(GLuint from, int fw, int fh, GLuint to, int tw, int th, bool depth) {
  const ApplyGl& g = agl();
  g.BindFramebuffer(GL_READ_FRAMEBUFFER, from);
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, to);
  GLint read_buffer = GL_COLOR_ATTACHMENT0;
  if (from) g.GetIntegerv(GL_READ_BUFFER, &read_buffer);
  if (from && read_buffer != GL_COLOR_ATTACHMENT0) g.ReadBuffer(GL_COLOR_ATTACHMENT0);
  g.BlitFramebuffer(0, 0, fw, fh, 0, 0, tw, th, GL_COLOR_BUFFER_BIT, GL_LINEAR);
  if (depth) g.BlitFramebuffer(0, 0, fw, fh, 0, 0, tw, th, GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, GL_NEAREST);
  if (from && read_buffer != GL_COLOR_ATTACHMENT0) g.ReadBuffer(static_cast<GLenum>(read_buffer));
}
}  // namespace

GLuint TargetScaler::single_sampled_window(bool depth) {
  if (window_.samples == 0) return window_.fbo;
  ensure_image_set(window_.resolve, window_.width, window_.height);
  blit_whole(window_.fbo, window_.width, window_.height, window_.resolve.fbo, window_.width, window_.height,
             depth && window_.depth);
  return window_.resolve.fbo;
}

void TargetScaler::present() {
  if (!window_.fbo) return warm_present();
  if (!blits()) return present_without_blits();
  BlitState saved;
  const GLuint from = single_sampled_window(false);
  if (window_.samples == 0) {
    blit_whole(from, window_.width, window_.height, 0, window_width_, window_height_, false);
    return;
  }
  // A multisampled window takes only a blit of its own size.
  ensure_image_set(window_.copy, window_width_, window_height_);
  blit_whole(from, window_.width, window_.height, window_.copy.fbo, window_width_, window_height_, false);
  blit_whole(window_.copy.fbo, window_width_, window_height_, 0, window_width_, window_height_, false);
}

void TargetScaler::bind_window_copy() {
  if (!blits()) return bind_window_copy_without_blits();
  ensure_image_set(window_.copy, window_width_, window_height_);
  {
    BlitState saved;
    const GLuint from = single_sampled_window(true);
    blit_whole(from, window_.width, window_.height, window_.copy.fbo, window_width_, window_height_,
               window_.depth != 0);
  }
  agl().BindFramebuffer(GL_READ_FRAMEBUFFER, window_.copy.fbo);
}

void TargetScaler::unbind_window_copy() {
  agl().BindFramebuffer(blits() ? GL_READ_FRAMEBUFFER : GL_FRAMEBUFFER, window_.fbo);
}

void TargetScaler::agl_bind_read_framebuffer(GLuint app) { agl().BindFramebuffer(GL_READ_FRAMEBUFFER, app); }

bool TargetScaler::depth_format(GLint format) { return buffer_bits(format) != GL_COLOR_BUFFER_BIT; }

bool TargetScaler::depth_texture(GLuint texture) const {
  const auto it = textures_.find(texture);
  return it != textures_.end() && depth_format(it->second.internal_format);
}

GLenum TargetScaler::kind_of(GLuint texture) const {
  const auto it = textures_.find(texture);
  return it == textures_.end() || it->second.app_size.empty() ? 0 : it->second.kind;
}

int full_mip_levels(int width, int height) {
  int levels = 1;
  while ((std::max(width, height) >> levels) > 0) ++levels;
  return levels;
}

GLint sized_internal_format(GLint format) {
  switch (format) {
    case GL_RGBA:
      return GL_RGBA8;
    case GL_RGB:
      return GL_RGB8;
    case GL_RG:
      return GL_RG8;
    case GL_RED:
      return GL_R8;
    case GL_SRGB_ALPHA:
      return GL_SRGB8_ALPHA8;
    case GL_SRGB:
      return GL_SRGB8;
    default:
      return format;
  }
}

namespace {
// The sized format a renderbuffer copy of an image of `format` takes; 0 where none is known
// (an unsized depth format: the driver picked its depth, and a depth blit needs the very same).
GLenum sized_for_copy(GLint format) {
  // Only formats a renderbuffer surely takes (legacy ones such as 3, 4 or GL_BGRA would raise an
  // error the app could read).
  const auto sized = static_cast<GLenum>(sized_internal_format(format));
  GLenum upload_format = 0, type = 0;
  if (!null_upload(sized, &upload_format, &type)) return 0;
  // Signed normalised (not integer) and 16-bit RGB formats are textures' only: no renderbuffer
  // takes them.
  const bool snorm = (type == GL_BYTE || type == GL_SHORT) && !is_integer_format(upload_format);
  return snorm || sized == GL_RGB16 ? 0 : sized;
}
}  // namespace

bool TargetScaler::bind_read_copy(GLint x, GLint y, GLsizei w, GLsizei h, bool depth_stencil) {
  const auto f = framebuffers_.find(read_fbo_);
  // Attachments changed since they were learnt: read as it is rather than from a stale image.
  if (f == framebuffers_.end() || f->second.scale == 1.0 || !f->second.attachments_known || w <= 0 || h <= 0)
    return false;
  const ApplyGl& g = agl();
  GLint read_buffer = GL_NONE;
  g.GetIntegerv(GL_READ_BUFFER, &read_buffer);
  const Image* image = nullptr;
  for (const Attachment& a : f->second.attachments) {
    const bool wanted = depth_stencil ? a.point == GL_DEPTH_ATTACHMENT || a.point == GL_STENCIL_ATTACHMENT
                                      : a.point == static_cast<GLenum>(read_buffer);
    if (!wanted) continue;
    const auto& images = a.renderbuffer ? renderbuffers_ : textures_;
    const auto it = images.find(a.name);
    if (it != images.end() && !it->second.app_size.empty()) image = &it->second;
    break;
  }
  if (!image || image->samples > 0) return false;
  const GLenum format = sized_for_copy(image->internal_format);
  if (!format) return false;
  const int app_w = image->app_size[0][0], app_h = image->app_size[0][1];
  GLint renderbuffer = 0, draw = 0;
  g.GetIntegerv(GL_RENDERBUFFER_BINDING, &renderbuffer);
  g.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  ReadCopy& c = read_copy_;
  if (!c.fbo || c.format != format || c.width != app_w || c.height != app_h) {
    if (!c.fbo) {
      g.GenFramebuffers(1, &c.fbo);
      g.GenRenderbuffers(1, &c.image);
    }
    g.BindRenderbuffer(GL_RENDERBUFFER, c.image);
    g.RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, format, app_w, app_h);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, c.fbo);
    if (c.depth != depth_stencil || c.format != format) {
      // One attachment point at a time, the one the format belongs to.
      g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, 0);
      g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, 0);
      g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, attachment_point(static_cast<GLint>(format)), GL_RENDERBUFFER,
                                c.image);
    }
    c.format = format;
    c.depth = depth_stencil;
    c.width = app_w;
    c.height = app_h;
  }
  // The rectangle and a texel around it, so that a small one maps to whole stored texels.
  const GLint box[4] = {std::max(0, x - 2), std::max(0, y - 2), std::min(app_w, x + w + 2), std::min(app_h, y + h + 2)};
  GLint from[4];
  double sx = 1.0, sy = 1.0;
  scale_of(read_fbo_, &sx, &sy);
  scale_corners(box, sx, sy, from);
  {
    BlitState saved;
    g.BindFramebuffer(GL_READ_FRAMEBUFFER, read_fbo_);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, c.fbo);
    g.BlitFramebuffer(from[0], from[1], from[2], from[3], box[0], box[1], box[2], box[3],
                      buffer_bits(image->internal_format), GL_NEAREST);
  }
  g.BindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(renderbuffer));
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
  g.BindFramebuffer(GL_READ_FRAMEBUFFER, c.fbo);
  if (!depth_stencil) g.ReadBuffer(GL_COLOR_ATTACHMENT0);
  return true;
}

double TargetScaler::scale_for(GLuint app_fbo, const Levels& config) const {
  if (app_fbo == 0) return window_scale_for(config);
  auto it = framebuffers_.find(app_fbo);
  return it == framebuffers_.end() ? 1.0 : scale_for(app_fbo, it->second, config);
}

double TargetScaler::scale_for(GLuint name, const Framebuffer& f, const Levels& config) const {
  const manifest::Manifest& m = active_manifest();
  double s = 1.0;
  for (size_t q = 0; q < m.passes.size(); ++q) {
    const manifest::Pass& pass = m.passes[q];
    const int l = config[static_cast<int>(q)];
    if (l < 0 || static_cast<size_t>(l) >= pass.levels.size()) continue;
    const manifest::Level& level = pass.levels[static_cast<size_t>(l)];
    if (level.scale == 1.0) continue;
    for (const manifest::Target& t : level.targets) {
      bool hit = false;
      switch (t.kind) {
        case manifest::Target::Kind::self:
          hit = (f.passes >> q) & 1;
          break;
        case manifest::Target::Kind::pass: {
          const int other = m.find(t.name);
          hit = other >= 0 && other < 64 && ((f.passes >> other) & 1);
          break;
        }
        case manifest::Target::Kind::framebuffer:
          hit = t.id == name;
          break;
        case manifest::Target::Kind::texture:
          for (const Attachment& a : f.attachments) hit |= !a.renderbuffer && a.name == t.id;
          break;
        case manifest::Target::Kind::window_sized:
          hit = window_sized(f);
          break;
        case manifest::Target::Kind::default_framebuffer:
          break;
      }
      if (hit) s = std::min(s, level.scale);
    }
  }
  return s;
}

// Every image the app gave the window's size (as the app specified it, whatever it is stored
// at now); a framebuffer with no known image is not.
bool TargetScaler::window_sized(const Framebuffer& f) const {
  if (f.attachments.empty() || window_width_ <= 0 || window_height_ <= 0) return false;
  for (const Attachment& a : f.attachments) {
    const auto& images = a.renderbuffer ? renderbuffers_ : textures_;
    auto it = images.find(a.name);
    if (it == images.end() || it->second.app_size.empty()) return false;
    if (it->second.app_size[0][0] != window_width_ || it->second.app_size[0][1] != window_height_) return false;
  }
  return true;
}

void TargetScaler::learn_attachments(Framebuffer& f, GLenum target) {
  // Asked of the framebuffer bound to `target`: for drawing, which is this one when a draw
  // reaches it.
  const ApplyGl& g = agl();
  f.attachments.clear();
  GLint colors = 8;
  g.GetIntegerv(GL_MAX_COLOR_ATTACHMENTS, &colors);
  std::vector<GLenum> points;
  for (GLint i = 0; i < colors; ++i) points.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  points.push_back(GL_DEPTH_ATTACHMENT);
  points.push_back(GL_STENCIL_ATTACHMENT);
  for (GLenum point : points) {
    GLint type = GL_NONE, name = 0;
    g.GetFramebufferAttachmentParameteriv(target, point, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type != GL_TEXTURE && type != GL_RENDERBUFFER) continue;
    g.GetFramebufferAttachmentParameteriv(target, point, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    const bool rb = type == GL_RENDERBUFFER;
    bool seen = false;  // a depth-stencil image answers for both points
    for (const Attachment& a : f.attachments) seen |= a.renderbuffer == rb && a.name == static_cast<GLuint>(name);
    if (!seen) f.attachments.push_back({point, rb, static_cast<GLuint>(name)});
  }
  f.attachments_known = true;
}

bool TargetScaler::cleared_before_drawn(const Framebuffer& f) const {
  if (f.drawn_frame + 1 != frame_ || f.cleared_frame != f.drawn_frame) return false;
  GLbitfield needed = 0;
  for (const Attachment& a : f.attachments) {
    const auto& images = a.renderbuffer ? renderbuffers_ : textures_;
    auto it = images.find(a.name);
    needed |= buffer_bits(it == images.end() ? 0 : it->second.internal_format);
  }
  return (f.cleared & needed) == needed;
}

void TargetScaler::on_clear(GLbitfield mask) {
  if (draw_fbo_ == 0 || !blits()) return;
  Framebuffer& f = framebuffers_[draw_fbo_];
  if (f.drawn_frame == frame_) return;           // drawn already this frame: a clear now is no fresh start
  if (agl().IsEnabled(GL_SCISSOR_TEST)) return;  // a partial clear
  if (f.cleared_frame != frame_) f.cleared = 0;
  f.cleared_frame = frame_;
  f.cleared |= mask;
}

void TargetScaler::on_draw(int pass) {
  if (draw_fbo_ == 0 || !blits()) return;
  Framebuffer& f = framebuffers_[draw_fbo_];
  f.drawn_frame = frame_;
  const bool new_pass = pass >= 0 && pass < 64 && !((f.passes >> pass) & 1);
  if (!new_pass && f.attachments_known) return;
  if (new_pass) f.passes |= uint64_t{1} << pass;
  if (!f.attachments_known) learn_attachments(f);
  const double before = f.scale;
  ensure_scale(draw_fbo_, f);
  if (f.scale != before) apply_viewport();
  warm_rescales(draw_fbo_, f);
}

void TargetScaler::on_blit(GLuint read, GLuint draw) {
  if (!blits()) return;
  const double before = draw_fbo_ ? framebuffers_[draw_fbo_].scale : 1.0;
  for (GLuint name : {read, draw}) {
    if (name == 0) continue;
    Framebuffer& f = framebuffers_[name];
    if (name == draw) f.drawn_frame = frame_;
    if (f.attachments_known) continue;
    // Learnt through the read binding, which the blit sets again itself.
    GLint bound = 0;
    agl().GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &bound);
    agl().BindFramebuffer(GL_READ_FRAMEBUFFER, name);
    learn_attachments(f, GL_READ_FRAMEBUFFER);
    ensure_scale(name, f);
    warm_rescales(name, f);
    agl().BindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(bound));
  }
  if (draw_fbo_ && framebuffers_[draw_fbo_].scale != before) apply_viewport();
}

void TargetScaler::ensure_scale(GLuint name, Framebuffer& f, bool carry) {
  double s = wanted_scale(name, f);
  // A framebuffer whose images are not all the scaler's keeps its size: scaling the others
  // would leave the app's full-size viewport drawing into part of the one it cannot scale.
  for (const Attachment& a : f.attachments) {
    if (s == 1.0) break;
    const auto& images = a.renderbuffer ? renderbuffers_ : textures_;
    const auto it = images.find(a.name);
    if (it != images.end() && !it->second.app_size.empty()) continue;
    if (!a.renderbuffer && viewed_.count(a.name)) {  // said when it was viewed
      f.scale = 1.0;
      return;
    }
    say_once(
        "unknown-image" + std::to_string(a.name),
        std::string(a.renderbuffer ? "renderbuffer " : "texture ") + std::to_string(a.name) + " of framebuffer " +
            std::to_string(name) +
            " was not made by glTexImage2D/3D, glTexImage2DMultisample, glRenderbufferStorage or glTex(ture)Storage* "
            "of a framebuffer format; "
            "the framebuffer is not scaled");
    // Its known images are left as they are: another framebuffer may share one (a depth
    // buffer) at its own scale.
    f.scale = 1.0;
    return;
  }
  f.scale = s;
  for (const Attachment& a : f.attachments) {
    auto& images = a.renderbuffer ? renderbuffers_ : textures_;
    auto it = images.find(a.name);
    if (it != images.end() && it->second.scale != s) rescale(a.name, it->second, s, carry);
  }
  any_scaled_ = any_scaled_ || s != 1.0;
}

namespace {
// The layers of a texture a framebuffer attaches one at a time: a cube map's faces, an
// array's layers, a 2D texture's one.
GLsizei attachable_layers(GLenum kind, GLsizei layers) {
  return kind == GL_TEXTURE_CUBE_MAP ? 6 : kind == GL_TEXTURE_2D ? 1 : layers;
}
}  // namespace

void TargetScaler::specify_level(const Image& image, GLint level, GLsizei width, GLsizei height) {
  const ApplyGl& g = agl();
  switch (image.kind) {
    case GL_TEXTURE_CUBE_MAP:
      for (GLenum face = 0; face < 6; ++face)
        g.TexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face, level, image.internal_format, width, height, 0,
                     image.format, image.type, nullptr);
      break;
    case GL_TEXTURE_2D_MULTISAMPLE:
      if (g.TexImage2DMultisample)
        g.TexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, image.samples, static_cast<GLenum>(image.internal_format),
                                width, height, image.fixed_locations);
      break;
    case GL_TEXTURE_2D_ARRAY:
    case GL_TEXTURE_CUBE_MAP_ARRAY:
      if (g.TexImage3D)
        g.TexImage3D(image.kind, level, image.internal_format, width, height, image.layers, 0, image.format, image.type,
                     nullptr);
      break;
    default:
      g.TexImage2D(GL_TEXTURE_2D, level, image.internal_format, width, height, 0, image.format, image.type, nullptr);
  }
}

void attach_texture_layer(GLenum target, GLenum point, GLenum kind, GLuint texture, GLint layer) {
  const ApplyGl& g = agl();
  if (kind == GL_TEXTURE_2D || kind == GL_TEXTURE_2D_MULTISAMPLE)
    g.FramebufferTexture2D(target, point, kind, texture, 0);
  else if (kind == GL_TEXTURE_CUBE_MAP)
    g.FramebufferTexture2D(target, point, GL_TEXTURE_CUBE_MAP_POSITIVE_X + static_cast<GLenum>(layer), texture, 0);
  else
    g.FramebufferTextureLayer(target, point, texture, 0, layer);
}

void TargetScaler::allocate_like(const Image& image, GLuint object, GLsizei width, GLsizei height, int level) {
  const ApplyGl& g = agl();
  if (image.renderbuffer) {
    g.BindRenderbuffer(GL_RENDERBUFFER, object);
    g.RenderbufferStorageMultisample(GL_RENDERBUFFER, image.samples, static_cast<GLenum>(image.internal_format), width,
                                     height);
  } else {
    g.BindTexture(image.kind, object);
    specify_level(image, level, width, height);
  }
}

void TargetScaler::attach_like(const Image& image, GLenum target, GLuint fbo, GLuint object, GLint layer) {
  agl().BindFramebuffer(target, fbo);
  const GLenum point = attachment_point(image.internal_format);
  if (image.renderbuffer)
    agl().FramebufferRenderbuffer(target, point, GL_RENDERBUFFER, object);
  else
    attach_texture_layer(target, point, image.kind, object, layer);
}

void TargetScaler::rescale(GLuint name, Image& image, double scale, bool carry_contents) {
  if (image.app_size.empty()) return;
  const ApplyGl& g = agl();
  SavedBindings saved(image.renderbuffer ? GL_TEXTURE_2D : image.kind);
  const GLsizei old_w = image.stored_width(), old_h = image.stored_height();
  const GLbitfield mask = buffer_bits(image.internal_format);
  const GLenum filter = stretch_filter(image.internal_format, image.format);
  // Contents are carried over (a clear made before the first draw that revealed the target,
  // or what a temporal effect keeps), except for multisampled images (blits between
  // multisampled images of different sizes do not exist).
  const GLsizei layers = image.renderbuffer ? 1 : attachable_layers(image.kind, image.layers);
  const bool carry = carry_contents && image.samples == 0 &&
                     (layers == 1 || image.kind == GL_TEXTURE_CUBE_MAP || g.FramebufferTextureLayer != nullptr);
  GLuint fbo[2] = {0, 0}, copy = 0;
  // Level 0, layer by layer, from `from` at its size into `to` at its own.
  auto blit_layers = [&](GLuint from, GLsizei fw, GLsizei fh, GLuint to, GLsizei tw, GLsizei th, GLenum how) {
    for (GLsizei layer = 0; layer < layers; ++layer) {
      attach_like(image, GL_READ_FRAMEBUFFER, fbo[0], from, layer);  // a cube map's face, an array's layer
      attach_like(image, GL_DRAW_FRAMEBUFFER, fbo[1], to, layer);
      g.BlitFramebuffer(0, 0, fw, fh, 0, 0, tw, th, mask, how);
    }
  };
  // The copy is made at the new size, so the larger of the two blits moves the smaller image.
  const GLsizei new_w = scaled(image.app_size[0][0], scale), new_h = scaled(image.app_size[0][1], scale);
  if (carry) {
    g.GenFramebuffers(2, fbo);
    if (image.renderbuffer)
      g.GenRenderbuffers(1, &copy);
    else
      g.GenTextures(1, &copy);
    allocate_like(image, copy, new_w, new_h, 0);
    blit_layers(name, old_w, old_h, copy, new_w, new_h, filter);
  }
  image.scale = scale;
  for (size_t level = 0; level < image.app_size.size(); ++level) {
    if (image.app_size[level][0] == 0) continue;
    const auto size = image.stored_level_size(level);
    allocate_like(image, name, size[0], size[1], static_cast<int>(level));
  }
  if (carry) {
    blit_layers(copy, new_w, new_h, name, new_w, new_h, GL_NEAREST);
    g.DeleteFramebuffers(2, fbo);
    if (image.renderbuffer)
      g.DeleteRenderbuffers(1, &copy);
    else
      g.DeleteTextures(1, &copy);
  }
}

bool TargetScaler::stored_at(GLuint app_fbo, double scale) const {
  if (app_fbo == 0) {
    if (!window_.fbo) return scale == 1.0;
    return window_.width == scaled(window_width_, scale) && window_.height == scaled(window_height_, scale);
  }
  auto it = framebuffers_.find(app_fbo);
  if (it == framebuffers_.end()) return scale == 1.0;
  for (const Attachment& a : it->second.attachments) {
    const auto& images = a.renderbuffer ? renderbuffers_ : textures_;
    auto im = images.find(a.name);
    // An image the scaler never saw specified is stored as the app made it.
    const double stored = im == images.end() || im->second.app_size.empty() ? 1.0 : im->second.scale;
    if (stored != scale) return false;
  }
  return true;
}

void TargetScaler::scale_of(GLuint fbo, double* sx, double* sy) const {
  *sx = *sy = 1.0;
  if (fbo == 0) {
    if (window_.fbo && window_width_ > 0 && window_height_ > 0) {
      *sx = static_cast<double>(window_.width) / window_width_;
      *sy = static_cast<double>(window_.height) / window_height_;
    }
    return;
  }
  auto it = framebuffers_.find(fbo);
  if (it == framebuffers_.end() || it->second.scale == 1.0) return;
  for (const Attachment& a : it->second.attachments) {
    const auto& images = a.renderbuffer ? renderbuffers_ : textures_;
    auto im = images.find(a.name);
    if (im == images.end() || im->second.app_size.empty()) continue;
    // Exact ratios, so that the app's full-size viewport becomes exactly the stored size.
    *sx = static_cast<double>(im->second.stored_width()) / im->second.app_size[0][0];
    *sy = static_cast<double>(im->second.stored_height()) / im->second.app_size[0][1];
    return;
  }
}

void scale_box(const GLint* in, double sx, double sy, GLint* out) {
  const auto x0 = std::lround(in[0] * sx), y0 = std::lround(in[1] * sy);
  out[0] = static_cast<GLint>(x0);
  out[1] = static_cast<GLint>(y0);
  out[2] = static_cast<GLint>(std::lround((in[0] + in[2]) * sx) - x0);
  out[3] = static_cast<GLint>(std::lround((in[1] + in[3]) * sy) - y0);
}

void scale_corners(const GLint* in, double sx, double sy, GLint* out) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<GLint>(std::lround(in[i] * (i % 2 ? sy : sx)));
}

void TargetScaler::apply_viewport() {
  double sx, sy;
  scale_of(draw_fbo_, &sx, &sy);
  if (!viewports_.empty()) return apply_indexed_boxes(sx, sy);
  const ApplyGl& g = agl();
  GLint v[4], s[4];
  scale_box(viewport_.data(), sx, sy, v);
  scale_box(scissor_.data(), sx, sy, s);
  g.Viewport(v[0], v[1], v[2], v[3]);
  g.Scissor(s[0], s[1], s[2], s[3]);
}

void TargetScaler::attrib_pushed(GLbitfield mask) {
  GLint depth = 0;
  agl().GetIntegerv(GL_ATTRIB_STACK_DEPTH, &depth);
  const size_t now = depth > 0 ? static_cast<size_t>(depth) : 0;
  // Nothing pushed (a full stack, or a push compiled into a display list): as deep as GL's.
  if (now <= attrib_stack_.size()) return attrib_stack_.resize(now);
  attrib_stack_.resize(now - 1);  // pushes made where the shim did not see them hold nothing
  attrib_stack_.push_back({mask, window_scaled(), viewport_, scissor_, viewports_, scissors_});
}

GLenum TargetScaler::window_name(GLenum attachment_buffer, bool double_buffered) {
  if (attachment_buffer == GL_COLOR_ATTACHMENT0) return double_buffered ? GL_BACK : GL_FRONT;
  return attachment_buffer;
}

void TargetScaler::pop_attrib(void (*pop)()) {
  const ApplyGl& g = agl();
  GLint depth = 0;
  g.GetIntegerv(GL_ATTRIB_STACK_DEPTH, &depth);
  const bool seen = depth > 0 && static_cast<size_t>(depth) == attrib_stack_.size();
  const GLbitfield mask = seen ? attrib_stack_.back().mask & (GL_COLOR_BUFFER_BIT | GL_PIXEL_MODE_BIT) : 0;
  const bool draw_window = draw_fbo_ == 0 && (mask & GL_COLOR_BUFFER_BIT);
  const bool read_window = read_fbo_ == 0 && (mask & GL_PIXEL_MODE_BIT);
  if (!seen || (!draw_window && !read_window) || attrib_stack_.back().window_scaled == window_scaled() ||
      !g.DrawBuffer) {
    pop();
    return attrib_popped();
  }
  const bool scaled_then = attrib_stack_.back().window_scaled;
  if (scaled_then && !attrib_fbo_) g.GenFramebuffers(1, &attrib_fbo_);
  const GLuint then = scaled_then ? attrib_fbo_ : 0;
  if (draw_window) g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, then);
  if (read_window) g.BindFramebuffer(GL_READ_FRAMEBUFFER, then);
  pop();
  GLint draw = GL_NONE, read = GL_NONE, double_buffered = GL_TRUE;
  if (draw_window) g.GetIntegerv(GL_DRAW_BUFFER, &draw);
  if (read_window) g.GetIntegerv(GL_READ_BUFFER, &read);
  if (!window_scaled()) {
    // Asked of the window itself: the shim answers the app GL_DOUBLEBUFFER from it too.
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    g.GetIntegerv(GL_DOUBLEBUFFER, &double_buffered);
  }
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, real_framebuffer(draw_fbo_));
  g.BindFramebuffer(GL_READ_FRAMEBUFFER, real_framebuffer(read_fbo_));
  const auto now = [&](GLint buffer) {
    const GLenum b = static_cast<GLenum>(buffer);
    return window_scaled() ? window_buffer(b) : window_name(b, double_buffered != GL_FALSE);
  };
  if (draw_window) g.DrawBuffer(now(draw));
  if (read_window) g.ReadBuffer(now(read));
  attrib_popped();
}

void TargetScaler::attrib_popped() {
  GLint depth = 0;
  agl().GetIntegerv(GL_ATTRIB_STACK_DEPTH, &depth);
  const size_t now = depth > 0 ? static_cast<size_t>(depth) : 0;
  if (now >= attrib_stack_.size()) return;  // an empty stack's pop: the driver's error
  const SavedBoxes popped = attrib_stack_[now];
  attrib_stack_.resize(now);
  // Boxes pushed before the app set any by index were all index 0's.
  if (popped.mask & GL_VIEWPORT_BIT) {
    viewport_ = popped.viewport;
    if (popped.viewports.size() == viewports_.size())
      viewports_ = popped.viewports;
    else
      for (auto& box : viewports_) box = float_box(viewport_);
  }
  if (popped.mask & GL_SCISSOR_BIT) {
    scissor_ = popped.scissor;
    if (popped.scissors.size() == scissors_.size())
      scissors_ = popped.scissors;
    else
      for (auto& box : scissors_) box = scissor_;
  }
  if (popped.mask & (GL_VIEWPORT_BIT | GL_SCISSOR_BIT)) apply_viewport();
}

void TargetScaler::bind_framebuffer(GLenum target, GLuint fbo) {
  double before_x, before_y, after_x, after_y;
  scale_of(draw_fbo_, &before_x, &before_y);
  if (target == GL_FRAMEBUFFER || target == GL_DRAW_FRAMEBUFFER) draw_fbo_ = fbo;
  if (target == GL_FRAMEBUFFER || target == GL_READ_FRAMEBUFFER) read_fbo_ = fbo;
  scale_of(draw_fbo_, &after_x, &after_y);
  if (before_x != after_x || before_y != after_y) apply_viewport();
}

void TargetScaler::framebuffer_attachment_changed(GLenum target) {
  named_framebuffer_attachment_changed(target == GL_READ_FRAMEBUFFER ? read_fbo_ : draw_fbo_);
}

void TargetScaler::named_framebuffer_attachment_changed(GLuint framebuffer) {
  ++attachment_changes_;
  auto it = framebuffers_.find(framebuffer);
  if (it != framebuffers_.end()) it->second.attachments_known = false;
}

void TargetScaler::framebuffers_deleted(GLsizei n, const GLuint* names) {
  for (GLsizei i = 0; names && i < n; ++i) {
    framebuffers_.erase(names[i]);
    if (names[i] == draw_fbo_) bind_framebuffer(GL_DRAW_FRAMEBUFFER, 0);
    if (names[i] == read_fbo_) read_fbo_ = 0;
  }
}

void TargetScaler::textures_deleted(GLsizei n, const GLuint* names) {
  for (GLsizei i = 0; names && i < n; ++i) {
    textures_.erase(names[i]);
    viewed_.erase(names[i]);  // the name may be made again, as anything
  }
}

void TargetScaler::renderbuffers_deleted(GLsizei n, const GLuint* names) {
  for (GLsizei i = 0; names && i < n; ++i) renderbuffers_.erase(names[i]);
}

void TargetScaler::set_box(std::array<GLint, 4>& box, void(APIENTRYP set)(GLint, GLint, GLsizei, GLsizei), GLint x,
                           GLint y, GLsizei w, GLsizei h) {
  box = {x, y, w, h};
  double sx, sy;
  scale_of(draw_fbo_, &sx, &sy);
  GLint b[4];
  scale_box(box.data(), sx, sy, b);
  set(b[0], b[1], b[2], b[3]);
}

// glViewport and glScissor set every index's box.
void TargetScaler::viewport(GLint x, GLint y, GLsizei w, GLsizei h) {
  set_box(viewport_, agl().Viewport, x, y, w, h);
  for (auto& box : viewports_) box = float_box(viewport_);
}

void TargetScaler::scissor(GLint x, GLint y, GLsizei w, GLsizei h) {
  set_box(scissor_, agl().Scissor, x, y, w, h);
  for (auto& box : scissors_) box = scissor_;
}

GLenum TargetScaler::binding_of(GLenum kind) {
  switch (kind) {
    case GL_TEXTURE_2D_ARRAY:
      return GL_TEXTURE_BINDING_2D_ARRAY;
    case GL_TEXTURE_CUBE_MAP:
      return GL_TEXTURE_BINDING_CUBE_MAP;
    case GL_TEXTURE_CUBE_MAP_ARRAY:
      return GL_TEXTURE_BINDING_CUBE_MAP_ARRAY;
    case GL_TEXTURE_2D_MULTISAMPLE:
      return GL_TEXTURE_BINDING_2D_MULTISAMPLE;
    default:
      return GL_TEXTURE_BINDING_2D;
  }
}

GLenum TargetScaler::texture_kind(GLenum target) {
  switch (target) {
    case GL_TEXTURE_2D:
    case GL_TEXTURE_2D_ARRAY:
    case GL_TEXTURE_CUBE_MAP:
    case GL_TEXTURE_CUBE_MAP_ARRAY:
    case GL_TEXTURE_2D_MULTISAMPLE:
      return target;
    default:
      return target >= GL_TEXTURE_CUBE_MAP_POSITIVE_X && target <= GL_TEXTURE_CUBE_MAP_NEGATIVE_Z ? GL_TEXTURE_CUBE_MAP
                                                                                                  : 0;
  }
}

void TargetScaler::tex_image(GLenum target, GLint level, GLint internal_format, GLsizei* width, GLsizei* height,
                             GLsizei layers, GLenum format, GLenum type, bool with_data) {
  const GLenum kind = texture_kind(target);
  if (!kind || level < 0 || level > 16 || !blits()) return;
  const GLuint bound = bound_texture(kind);
  if (!bound || viewed_.count(bound)) return;
  Image& im = textures_[bound];
  im.kind = kind;
  if (level == 0) {
    im.internal_format = internal_format;
    im.format = format;
    im.type = type;
    im.layers = std::max<GLsizei>(1, layers);
  }
  if (im.app_size.size() <= static_cast<size_t>(level)) im.app_size.resize(static_cast<size_t>(level) + 1, {0, 0});
  im.app_size[static_cast<size_t>(level)] = {*width, *height};
  if (im.scale == 1.0) return;
  if (with_data) {
    // The app's texels are for its own size: stored unscaled, the framebuffer rescales it.
    im.scale = 1.0;
    for (auto& [name, f] : framebuffers_)
      for (const Attachment& a : f.attachments)
        if (!a.renderbuffer && a.name == bound) f.scale = -1.0;  // re-check
    return;
  }
  const auto size = im.stored_level_size(static_cast<size_t>(level));
  *width = size[0];
  *height = size[1];
}

GLuint TargetScaler::bound_texture(GLenum target) const {
  const GLenum kind = texture_kind(target);
  if (!kind) return 0;
  GLint bound = 0;
  agl().GetIntegerv(binding_of(kind), &bound);
  return static_cast<GLuint>(bound);
}

bool TargetScaler::tex_storage(GLenum kind, GLuint texture, GLsizei levels, GLenum internal_format, GLsizei width,
                               GLsizei height, GLsizei layers) {
  GLenum format = 0, type = 0;
  // Other calls (and the app's mistakes, which must raise the driver's errors) go as they are.
  if (!blits() || !texture || texture_kind(kind) != kind || levels < 1 || width <= 0 || height <= 0 || layers < 1 ||
      !null_upload(internal_format, &format, &type))
    return false;
  if (levels > full_mip_levels(width, height)) return false;
  if ((kind == GL_TEXTURE_CUBE_MAP || kind == GL_TEXTURE_CUBE_MAP_ARRAY) && width != height) return false;
  if (kind == GL_TEXTURE_CUBE_MAP_ARRAY && layers % 6 != 0) return false;
  if (levels > 1 && !(width == window_width_ && height == window_height_) && !named_by_manifest(texture)) return false;
  if (caps_.gles && !in_gles(internal_format)) return false;
  const auto known = textures_.find(texture);
  if (known != textures_.end() && known->second.storage_levels) return false;  // immutable already: the driver's error
  if (viewed_.count(texture)) return false;
  const ApplyGl& g = agl();
  if (kind != GL_TEXTURE_2D && kind != GL_TEXTURE_CUBE_MAP && !g.TexImage3D) return false;
  SavedBindings saved(kind);  // the kind's binding, and no pixel-unpack buffer: no data
  g.BindTexture(kind, texture);
  // Every face of a cube map is specified through its face's target, which tex_image takes.
  const GLenum target = kind == GL_TEXTURE_CUBE_MAP ? GL_TEXTURE_CUBE_MAP_POSITIVE_X : kind;
  for (GLsizei level = 0; level < levels; ++level) {
    GLsizei w = std::max(1, width >> level), h = std::max(1, height >> level);
    tex_image(target, level, static_cast<GLint>(internal_format), &w, &h, layers, format, type, false);
    specify_level(textures_[texture], level, w, h);
  }
  // The levels the app may have set before: they went to the driver as they were.
  GLint base = 0, max = 1000;
  g.GetTexParameteriv(kind, GL_TEXTURE_BASE_LEVEL, &base);
  g.GetTexParameteriv(kind, GL_TEXTURE_MAX_LEVEL, &max);
  textures_[texture].storage_levels = levels;
  g.TexParameteri(kind, GL_TEXTURE_BASE_LEVEL, texture_parameter(texture, GL_TEXTURE_BASE_LEVEL, base));
  g.TexParameteri(kind, GL_TEXTURE_MAX_LEVEL, texture_parameter(texture, GL_TEXTURE_MAX_LEVEL, max));
  return true;
}

void TargetScaler::tex_image_multisample(GLsizei samples, GLenum internal_format, GLsizei* width, GLsizei* height,
                                         GLboolean fixed_locations) {
  const GLuint bound = blits() ? bound_texture(GL_TEXTURE_2D_MULTISAMPLE) : 0;
  if (!bound) return;
  Image& im = textures_[bound];
  im.kind = GL_TEXTURE_2D_MULTISAMPLE;
  im.samples = samples;
  im.fixed_locations = fixed_locations;
  im.internal_format = static_cast<GLint>(internal_format);
  im.app_size.assign(1, {*width, *height});
  if (im.scale == 1.0) return;
  *width = scaled(*width, im.scale);
  *height = scaled(*height, im.scale);
}

bool TargetScaler::tex_storage_multisample(GLuint texture, GLsizei samples, GLenum internal_format, GLsizei width,
                                           GLsizei height, GLboolean fixed_locations) {
  GLenum format = 0, type = 0;
  const ApplyGl& g = agl();
  // GLES has no mutable multisample textures: there it stays immutable, at its size.
  if (caps_.gles || !g.TexImage2DMultisample || !texture || samples < 0 || width <= 0 || height <= 0 ||
      !null_upload(internal_format, &format, &type))
    return false;
  const auto known = textures_.find(texture);
  if (known != textures_.end() && known->second.storage_levels) return false;  // immutable already: the driver's error
  SavedBindings saved(GL_TEXTURE_2D_MULTISAMPLE);
  g.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, texture);
  tex_image_multisample(samples, internal_format, &width, &height, fixed_locations);
  g.TexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, samples, internal_format, width, height, fixed_locations);
  textures_[texture].storage_levels = 1;
  return true;
}

void TargetScaler::texture_viewed(GLuint texture) {
  const auto it = textures_.find(texture);
  if (it == textures_.end() || !it->second.storage_levels) return;  // the driver's own storage, or none
  using Storage2D = void(APIENTRYP)(GLenum, GLsizei, GLenum, GLsizei, GLsizei);
  using Storage3D = void(APIENTRYP)(GLenum, GLsizei, GLenum, GLsizei, GLsizei, GLsizei);
  using Storage2DMultisample = void(APIENTRYP)(GLenum, GLsizei, GLenum, GLsizei, GLsizei, GLboolean);
  using CopyImage = void(APIENTRYP)(GLuint, GLenum, GLint, GLint, GLint, GLint, GLuint, GLenum, GLint, GLint, GLint,
                                    GLint, GLsizei, GLsizei, GLsizei);
  static const auto storage_2d = reinterpret_cast<Storage2D>(resolve_gl("glTexStorage2D"));
  static const auto storage_3d = reinterpret_cast<Storage3D>(resolve_gl("glTexStorage3D"));
  static const auto storage_2d_ms = reinterpret_cast<Storage2DMultisample>(resolve_gl("glTexStorage2DMultisample"));
  static const auto copy_image = reinterpret_cast<CopyImage>(resolve_gl("glCopyImageSubData"));
  if (!storage_2d || !copy_image) return;  // no views either (GL 4.3): the driver's answer stands
  // Back to the app's size, with the framebuffers it is in: the view sees the app's texels.
  for (auto& [name, f] : framebuffers_) {
    bool holds = false;
    for (const Attachment& a : f.attachments) holds |= !a.renderbuffer && a.name == texture;
    if (!holds || f.scale == 1.0) continue;
    for (const Attachment& a : f.attachments) {
      auto& images = a.renderbuffer ? renderbuffers_ : textures_;
      const auto im = images.find(a.name);
      if (im != images.end() && im->second.scale != 1.0) rescale(a.name, im->second, 1.0, true);
    }
    f.scale = 1.0;
  }
  const Image image = it->second;
  textures_.erase(it);
  viewed_.insert(texture);
  say_once("viewed" + std::to_string(texture),
           "texture " + std::to_string(texture) +
               " is viewed through glTextureView, which needs immutable storage: it keeps its size, and so do the "
               "framebuffers it is attached to");
  const ApplyGl& g = agl();
  SavedBindings saved(image.kind);
  const GLenum kind = image.kind;
  const GLenum format = static_cast<GLenum>(image.internal_format);
  const GLsizei levels = image.storage_levels, w = image.app_size[0][0], h = image.app_size[0][1];
  const GLsizei depth = kind == GL_TEXTURE_CUBE_MAP ? 6 : image.layers;
  auto make_storage = [&](GLuint name) {
    g.BindTexture(kind, name);
    if (kind == GL_TEXTURE_2D_MULTISAMPLE) {
      if (storage_2d_ms) storage_2d_ms(kind, image.samples, format, w, h, image.fixed_locations);
    } else if (kind == GL_TEXTURE_2D || kind == GL_TEXTURE_CUBE_MAP) {
      storage_2d(kind, levels, format, w, h);
    } else if (storage_3d) {
      storage_3d(kind, levels, format, w, h, image.layers);
    }
  };
  // The texels go through a copy of the same format: immutable storage replaces a texture's
  // images, so it is made on the app's name only once they are safe.
  GLuint copy = 0;
  g.GenTextures(1, &copy);
  make_storage(copy);
  auto copy_levels = [&](GLuint from, GLuint to) {
    for (GLsizei level = 0; level < levels; ++level)
      copy_image(from, kind, level, 0, 0, 0, to, kind, level, 0, 0, 0, std::max(1, w >> level), std::max(1, h >> level),
                 depth);
  };
  copy_levels(texture, copy);
  // The levels as the app set them, while the storage is mutable: an immutable texture clamps
  // what it is given from then on, as the app's own would have.
  g.BindTexture(kind, texture);
  if (kind != GL_TEXTURE_2D_MULTISAMPLE) {
    g.TexParameteri(kind, GL_TEXTURE_BASE_LEVEL, image.app_base_level);
    g.TexParameteri(kind, GL_TEXTURE_MAX_LEVEL, image.app_max_level);
  }
  make_storage(texture);
  copy_levels(copy, texture);
  g.DeleteTextures(1, &copy);
}

bool TargetScaler::named_by_manifest(GLuint texture) const {
  for (const manifest::Pass& pass : active_manifest().passes)
    for (const manifest::Level& level : pass.levels)
      for (const manifest::Target& t : level.targets)
        if (t.kind == manifest::Target::Kind::texture && t.id == texture) return true;
  return false;
}

bool TargetScaler::storage_parameter(GLuint texture, GLenum pname, GLint* value) const {
  if (!storage_pname(pname)) return false;
  const auto it = textures_.find(texture);
  if (!texture || it == textures_.end() || !it->second.storage_levels) return false;
  const Image& im = it->second;
  *value = pname == GL_TEXTURE_IMMUTABLE_FORMAT   ? GL_TRUE
           : pname == GL_TEXTURE_IMMUTABLE_LEVELS ? im.storage_levels
           : pname == GL_TEXTURE_BASE_LEVEL       ? im.app_base_level
                                                  : im.app_max_level;
  return true;
}

GLint TargetScaler::texture_parameter(GLuint texture, GLenum pname, GLint value) {
  if (!level_pname(pname)) return value;
  const auto it = textures_.find(texture);
  if (!texture || it == textures_.end() || !it->second.storage_levels) return value;
  // A negative value is the driver's error, passed on (and not kept).
  if (value < 0) return value;
  Image& im = it->second;
  (pname == GL_TEXTURE_BASE_LEVEL ? im.app_base_level : im.app_max_level) = value;
  // An immutable texture's base level is clamped to [0, levels - 1], its maximum to
  // [base, levels - 1] (a maximum set before a higher base is not sent again).
  const GLint last = im.storage_levels - 1;
  const GLint base = std::clamp(im.app_base_level, 0, last);
  return pname == GL_TEXTURE_BASE_LEVEL ? base : std::clamp(value, base, last);
}

void TargetScaler::renderbuffer_storage(GLsizei samples, GLenum internal_format, GLsizei* width, GLsizei* height) {
  if (!blits()) return;
  GLint bound = 0;
  agl().GetIntegerv(GL_RENDERBUFFER_BINDING, &bound);
  if (!bound) return;
  Image& im = renderbuffers_[static_cast<GLuint>(bound)];
  im.renderbuffer = true;
  im.samples = samples;
  im.internal_format = static_cast<GLint>(internal_format);
  im.app_size.assign(1, {*width, *height});
  if (im.scale == 1.0) return;
  *width = scaled(*width, im.scale);
  *height = scaled(*height, im.scale);
}

void TargetScaler::blit_rectangles(GLuint read, GLuint draw, GLint* src, GLint* dst) const {
  double sx, sy;
  scale_of(read, &sx, &sy);
  scale_corners(src, sx, sy, src);
  scale_of(draw, &sx, &sy);
  scale_corners(dst, sx, sy, dst);
}

bool TargetScaler::blit_multisampled_window(GLuint read, GLuint draw, const GLint* src, const GLint* dst,
                                            GLbitfield mask, GLenum filter) {
  if (!window_.fbo || window_.samples == 0 || (read != 0) == (draw != 0)) return false;
  if (std::abs(src[2] - src[0]) == std::abs(dst[2] - dst[0]) && std::abs(src[3] - src[1]) == std::abs(dst[3] - dst[1]))
    return false;
  const ApplyGl& g = agl();
  BlitState saved;
  if (draw == 0) {
    // Into the stand-in: stretched into the resolve image, then copied at its own size.
    ensure_image_set(window_.resolve, window_.width, window_.height);
    g.BindFramebuffer(GL_READ_FRAMEBUFFER, read);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, window_.resolve.fbo);
    g.BlitFramebuffer(src[0], src[1], src[2], src[3], dst[0], dst[1], dst[2], dst[3], mask, filter);
    g.BindFramebuffer(GL_READ_FRAMEBUFFER, window_.resolve.fbo);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, window_.fbo);
    g.BlitFramebuffer(dst[0], dst[1], dst[2], dst[3], dst[0], dst[1], dst[2], dst[3], mask, GL_NEAREST);
  } else {
    // Out of the stand-in: resolved at its own size, then stretched.
    const GLuint from = single_sampled_window((mask & (GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT)) != 0);
    g.BindFramebuffer(GL_READ_FRAMEBUFFER, from);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, draw);
    g.BlitFramebuffer(src[0], src[1], src[2], src[3], dst[0], dst[1], dst[2], dst[3], mask, filter);
  }
  return true;
}

bool TargetScaler::texture_size(GLuint texture, GLint level, GLenum pname, GLint* value) const {
  if (!size_pname(pname)) return false;
  auto it = textures_.find(texture);
  if (it == textures_.end() || it->second.scale == 1.0 || level < 0 ||
      static_cast<size_t>(level) >= it->second.app_size.size())
    return false;
  *value = it->second.app_size[static_cast<size_t>(level)][pname == GL_TEXTURE_WIDTH ? 0 : 1];
  return true;
}

bool TargetScaler::app_texture_size(GLuint texture, GLint* width, GLint* height, bool* scaled) const {
  auto it = textures_.find(texture);
  if (it == textures_.end() || it->second.app_size.empty()) return false;
  *width = it->second.app_size[0][0];
  *height = it->second.app_size[0][1];
  *scaled = it->second.scale != 1.0;
  return *width > 0 && *height > 0;
}

GLuint TargetScaler::texture_at_unit(GLint unit) {
  const ApplyGl& g = agl();
  if (texture_units_ < 0) g.GetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &texture_units_);
  if (unit < 0 || unit >= texture_units_ || !g.ActiveTexture) return 0;
  GLint active = GL_TEXTURE0, bound = 0;
  g.GetIntegerv(GL_ACTIVE_TEXTURE, &active);
  g.ActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
  g.GetIntegerv(GL_TEXTURE_BINDING_2D, &bound);
  g.ActiveTexture(static_cast<GLenum>(active));
  return static_cast<GLuint>(bound);
}

bool TargetScaler::renderbuffer_size(GLenum pname, GLint* value) const {
  if (pname != GL_RENDERBUFFER_WIDTH && pname != GL_RENDERBUFFER_HEIGHT) return false;
  GLint bound = 0;
  agl().GetIntegerv(GL_RENDERBUFFER_BINDING, &bound);
  auto it = renderbuffers_.find(static_cast<GLuint>(bound));
  if (it == renderbuffers_.end() || it->second.scale == 1.0 || it->second.app_size.empty()) return false;
  *value = it->second.app_size[0][pname == GL_RENDERBUFFER_WIDTH ? 0 : 1];
  return true;
}

}  // namespace glbudget

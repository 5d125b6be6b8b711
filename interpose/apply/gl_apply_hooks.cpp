// The app's calls that meet render-target scaling and program shadowing: framebuffer and image
// life cycle, viewport and scissor, blits, and the queries that must answer for the app.
#include <algorithm>
#include <vector>

#include "apply_gl.hpp"
#include "configuration.hpp"
#include "context_state.hpp"
#include "hooks_generated.hpp"
#include "hook_table.hpp"
#include "render_targets.hpp"
#include "probes.hpp"

namespace glbudget {

namespace {
TargetScaler* scaler() {
  ContextState* c = current_context();
  return c ? c->targets.get() : nullptr;
}

// What glGet* reports for the app: its own program and its own viewport and scissor box.
template <typename T>
void answer_for_app(GLenum pname, T* params) {
  ContextState* c = current_context();
  if (!c || !params) return;
  TargetScaler* s = c->targets.get();
  if (pname == GL_CURRENT_PROGRAM && c->bound_variants) {
    params[0] = static_cast<T>(c->program);
  } else if (pname == GL_NUM_PROGRAM_BINARY_FORMATS && shadows_programs(*c)) {
    // An app that loads cached binaries never gives its sources for the manifest to match: with
    // no binary format, apps build from source, as after a driver update.
    params[0] = 0;
  } else if (s && s->window_scaled() &&
             (pname == GL_DRAW_FRAMEBUFFER_BINDING || pname == GL_READ_FRAMEBUFFER_BINDING)) {
    params[0] =
        static_cast<T>(pname == GL_READ_FRAMEBUFFER_BINDING ? s->app_read_framebuffer() : s->app_draw_framebuffer());
  } else if (s && s->window_scaled() &&
             (pname == GL_DRAW_BUFFER || pname == GL_DRAW_BUFFER0 || pname == GL_READ_BUFFER)) {
    // The stand-in's GL_COLOR_ATTACHMENT0 is the window's back buffer to the app.
    const GLuint app = pname == GL_READ_BUFFER ? s->app_read_framebuffer() : s->app_draw_framebuffer();
    if (app == 0 && params[0] == static_cast<T>(GL_COLOR_ATTACHMENT0)) params[0] = static_cast<T>(GL_BACK);
  } else if ((pname == GL_VIEWPORT || pname == GL_SCISSOR_BOX) && s && s->boxes_scaled()) {
    // The window's stand-in scales them too: an app that saves its viewport and sets it again
    // would otherwise get it scaled twice.
    const GLint* box = pname == GL_VIEWPORT ? s->app_viewport() : s->app_scissor();
    for (int i = 0; i < 4; ++i) params[i] = static_cast<T>(box[i]);
  }
}

// What the app asks of the framebuffer drawn into, where that is the window: the window's own
// answer, not the stand-in's (an FBO, single-buffered: GL_DOUBLEBUFFER 0 made Warzone 2100 refuse
// to start at a scaled resolution).
bool describes_draw_framebuffer(GLenum pname) {
  switch (pname) {
    case GL_DOUBLEBUFFER:
    case GL_STEREO:
    case GL_SAMPLES:
    case GL_SAMPLE_BUFFERS:
    case GL_RED_BITS:
    case GL_GREEN_BITS:
    case GL_BLUE_BITS:
    case GL_ALPHA_BITS:
    case GL_DEPTH_BITS:
    case GL_STENCIL_BITS:
      return true;
    default:
      return false;
  }
}

template <typename Ask>
void ask_of_window(GLenum pname, Ask ask) {
  TargetScaler* s = describes_draw_framebuffer(pname) ? scaler() : nullptr;
  if (!s || !s->window_scaled() || s->app_draw_framebuffer() != 0) return ask();
  const ApplyGl& g = agl();
  GLint draw = 0;
  g.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  ask();
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
}
}  // namespace

void handle_glGetIntegerv(pfn_glGetIntegerv real, GLenum pname, GLint* data) {
  ask_of_window(pname, [&] { real(pname, data); });
  answer_for_app(pname, data);
}
void handle_glGetInteger64v(pfn_glGetInteger64v real, GLenum pname, GLint64* data) {
  ask_of_window(pname, [&] { real(pname, data); });
  answer_for_app(pname, data);
}
void handle_glGetFloatv(pfn_glGetFloatv real, GLenum pname, GLfloat* data) {
  ask_of_window(pname, [&] { real(pname, data); });
  answer_for_app(pname, data);
}
void handle_glGetDoublev(pfn_glGetDoublev real, GLenum pname, GLdouble* data) {
  ask_of_window(pname, [&] { real(pname, data); });
  answer_for_app(pname, data);
}
void handle_glGetBooleanv(pfn_glGetBooleanv real, GLenum pname, GLboolean* data) {
  ask_of_window(pname, [&] { real(pname, data); });
  if (pname == GL_CURRENT_PROGRAM) answer_for_app(pname, data);  // boxes as booleans mean nothing
}

void handle_glBindFramebuffer(pfn_glBindFramebuffer real, GLenum target, GLuint framebuffer) {
  ContextState* c = current_context();
  if (!c || !c->targets) return real(target, framebuffer);
  real(target, c->targets->real_framebuffer(framebuffer));
  c->targets->bind_framebuffer(target, framebuffer);
  if (target != GL_READ_FRAMEBUFFER) c->counter->invalidate();  // the next draw may reveal a target
}

void handle_glFramebufferTexture2D(pfn_glFramebufferTexture2D real, GLenum target, GLenum attachment, GLenum textarget,
                                   GLuint texture, GLint level) {
  real(target, attachment, textarget, texture, level);
  if (TargetScaler* s = scaler()) s->framebuffer_attachment_changed(target);
}

void handle_glFramebufferTexture(pfn_glFramebufferTexture real, GLenum target, GLenum attachment, GLuint texture,
                                 GLint level) {
  real(target, attachment, texture, level);
  if (TargetScaler* s = scaler()) s->framebuffer_attachment_changed(target);
}

void handle_glFramebufferTextureLayer(pfn_glFramebufferTextureLayer real, GLenum target, GLenum attachment,
                                      GLuint texture, GLint level, GLint layer) {
  real(target, attachment, texture, level, layer);
  if (TargetScaler* s = scaler()) s->framebuffer_attachment_changed(target);
}

void handle_glNamedFramebufferTexture(pfn_glNamedFramebufferTexture real, GLuint framebuffer, GLenum attachment,
                                      GLuint texture, GLint level) {
  real(framebuffer, attachment, texture, level);
  if (TargetScaler* s = scaler()) s->named_framebuffer_attachment_changed(framebuffer);
}

void handle_glNamedFramebufferTextureLayer(pfn_glNamedFramebufferTextureLayer real, GLuint framebuffer,
                                           GLenum attachment, GLuint texture, GLint level, GLint layer) {
  real(framebuffer, attachment, texture, level, layer);
  if (TargetScaler* s = scaler()) s->named_framebuffer_attachment_changed(framebuffer);
}

void handle_glNamedFramebufferRenderbuffer(pfn_glNamedFramebufferRenderbuffer real, GLuint framebuffer,
                                           GLenum attachment, GLenum renderbuffertarget, GLuint renderbuffer) {
  real(framebuffer, attachment, renderbuffertarget, renderbuffer);
  if (TargetScaler* s = scaler()) s->named_framebuffer_attachment_changed(framebuffer);
}

void handle_glFramebufferRenderbuffer(pfn_glFramebufferRenderbuffer real, GLenum target, GLenum attachment,
                                      GLenum renderbuffertarget, GLuint renderbuffer) {
  real(target, attachment, renderbuffertarget, renderbuffer);
  if (TargetScaler* s = scaler()) s->framebuffer_attachment_changed(target);
}

void handle_glDeleteFramebuffers(pfn_glDeleteFramebuffers real, GLsizei n, const GLuint* framebuffers) {
  real(n, framebuffers);
  if (TargetScaler* s = scaler()) s->framebuffers_deleted(n, framebuffers);
}

void handle_glDeleteTextures(pfn_glDeleteTextures real, GLsizei n, const GLuint* textures) {
  real(n, textures);
  if (TargetScaler* s = scaler()) s->textures_deleted(n, textures);
}

void handle_glDeleteRenderbuffers(pfn_glDeleteRenderbuffers real, GLsizei n, const GLuint* renderbuffers) {
  real(n, renderbuffers);
  if (TargetScaler* s = scaler()) s->renderbuffers_deleted(n, renderbuffers);
}

void handle_glViewport(pfn_glViewport real, GLint x, GLint y, GLsizei width, GLsizei height) {
  TargetScaler* s = scaler();
  if (!s || width < 0 || height < 0) return real(x, y, width, height);  // errors stay the driver's
  s->viewport(x, y, width, height);
}

void handle_glScissor(pfn_glScissor real, GLint x, GLint y, GLsizei width, GLsizei height) {
  TargetScaler* s = scaler();
  if (!s || width < 0 || height < 0) return real(x, y, width, height);
  s->scissor(x, y, width, height);
}

namespace {
// With an unpack buffer bound, a glTexImage's `pixels` is an offset into it: data all the same.
bool uploads_data(const void* pixels) {
  if (pixels) return true;
  GLint unpack = 0;
  static const auto get = reinterpret_cast<pfn_glGetIntegerv>(resolve_real(kHook_glGetIntegerv));
  if (get) get(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack);
  return unpack != 0;
}

// The kind of a texture named by a DSA call (GL_TEXTURE_TARGET), 0 where not one scaled here.
GLenum named_texture_kind(GLuint texture) {
  static const auto get = reinterpret_cast<pfn_glGetTextureParameteriv>(resolve_real(kHook_glGetTextureParameteriv));
  GLint target = 0;
  if (get && texture) get(texture, GL_TEXTURE_TARGET, &target);
  return TargetScaler::texture_kind(static_cast<GLenum>(target));
}
}  // namespace

void handle_glTexImage2D(pfn_glTexImage2D real, GLenum target, GLint level, GLint internalformat, GLsizei width,
                         GLsizei height, GLint border, GLenum format, GLenum type, const void* pixels) {
  TargetScaler* s = scaler();
  // GL_TEXTURE_2D or a cube map's face; other targets (a 1D array, the app's mistakes) as they are.
  const bool face = TargetScaler::texture_kind(target) == GL_TEXTURE_CUBE_MAP && target != GL_TEXTURE_CUBE_MAP;
  if (s && (target == GL_TEXTURE_2D || face) && width > 0 && height > 0)
    s->tex_image(target, level, internalformat, &width, &height, 1, format, type, uploads_data(pixels));
  real(target, level, internalformat, width, height, border, format, type, pixels);
}

void handle_glTexImage3D(pfn_glTexImage3D real, GLenum target, GLint level, GLint internalformat, GLsizei width,
                         GLsizei height, GLsizei depth, GLint border, GLenum format, GLenum type, const void* pixels) {
  TargetScaler* s = scaler();
  if (s && (target == GL_TEXTURE_2D_ARRAY || target == GL_TEXTURE_CUBE_MAP_ARRAY) && width > 0 && height > 0 &&
      depth > 0)
    s->tex_image(target, level, internalformat, &width, &height, depth, format, type, uploads_data(pixels));
  real(target, level, internalformat, width, height, depth, border, format, type, pixels);
}

void handle_glTexStorage2D(pfn_glTexStorage2D real, GLenum target, GLsizei levels, GLenum internalformat, GLsizei width,
                           GLsizei height) {
  TargetScaler* s = scaler();
  if (s && (target == GL_TEXTURE_2D || target == GL_TEXTURE_CUBE_MAP) &&
      s->tex_storage(target, s->bound_texture(target), levels, internalformat, width, height, 1))
    return;
  real(target, levels, internalformat, width, height);
}

void handle_glTextureStorage2D(pfn_glTextureStorage2D real, GLuint texture, GLsizei levels, GLenum internalformat,
                               GLsizei width, GLsizei height) {
  if (TargetScaler* s = scaler()) {
    // Named, the texture may be of any target that takes 2D storage (arrays of 1D among them).
    const GLenum kind = named_texture_kind(texture);
    if ((kind == GL_TEXTURE_2D || kind == GL_TEXTURE_CUBE_MAP) &&
        s->tex_storage(kind, texture, levels, internalformat, width, height, 1))
      return;
  }
  real(texture, levels, internalformat, width, height);
}

void handle_glTexImage2DMultisample(pfn_glTexImage2DMultisample real, GLenum target, GLsizei samples,
                                    GLenum internalformat, GLsizei width, GLsizei height,
                                    GLboolean fixedsamplelocations) {
  TargetScaler* s = scaler();
  if (s && target == GL_TEXTURE_2D_MULTISAMPLE && width > 0 && height > 0)
    s->tex_image_multisample(samples, internalformat, &width, &height, fixedsamplelocations);
  real(target, samples, internalformat, width, height, fixedsamplelocations);
}

void handle_glTexStorage2DMultisample(pfn_glTexStorage2DMultisample real, GLenum target, GLsizei samples,
                                      GLenum internalformat, GLsizei width, GLsizei height,
                                      GLboolean fixedsamplelocations) {
  TargetScaler* s = scaler();
  if (s && target == GL_TEXTURE_2D_MULTISAMPLE &&
      s->tex_storage_multisample(s->bound_texture(target), samples, internalformat, width, height,
                                 fixedsamplelocations))
    return;
  real(target, samples, internalformat, width, height, fixedsamplelocations);
}

void handle_glTextureStorage2DMultisample(pfn_glTextureStorage2DMultisample real, GLuint texture, GLsizei samples,
                                          GLenum internalformat, GLsizei width, GLsizei height,
                                          GLboolean fixedsamplelocations) {
  if (TargetScaler* s = scaler();
      s && named_texture_kind(texture) == GL_TEXTURE_2D_MULTISAMPLE &&
      s->tex_storage_multisample(texture, samples, internalformat, width, height, fixedsamplelocations))
    return;
  real(texture, samples, internalformat, width, height, fixedsamplelocations);
}

void handle_glTexStorage3D(pfn_glTexStorage3D real, GLenum target, GLsizei levels, GLenum internalformat, GLsizei width,
                           GLsizei height, GLsizei depth) {
  TargetScaler* s = scaler();
  if (s && (target == GL_TEXTURE_2D_ARRAY || target == GL_TEXTURE_CUBE_MAP_ARRAY) &&
      s->tex_storage(target, s->bound_texture(target), levels, internalformat, width, height, depth))
    return;
  real(target, levels, internalformat, width, height, depth);
}

void handle_glTextureStorage3D(pfn_glTextureStorage3D real, GLuint texture, GLsizei levels, GLenum internalformat,
                               GLsizei width, GLsizei height, GLsizei depth) {
  if (TargetScaler* s = scaler()) {
    const GLenum kind = named_texture_kind(texture);
    if ((kind == GL_TEXTURE_2D_ARRAY || kind == GL_TEXTURE_CUBE_MAP_ARRAY) &&
        s->tex_storage(kind, texture, levels, internalformat, width, height, depth))
      return;
  }
  real(texture, levels, internalformat, width, height, depth);
}

void handle_glGetTexParameteriv(pfn_glGetTexParameteriv real, GLenum target, GLenum pname, GLint* params) {
  TargetScaler* s = scaler();
  if (s && TargetScaler::texture_kind(target) == target && params && TargetScaler::storage_pname(pname) &&
      s->storage_parameter(s->bound_texture(target), pname, params))
    return;
  real(target, pname, params);
}

void handle_glGetTextureParameteriv(pfn_glGetTextureParameteriv real, GLuint texture, GLenum pname, GLint* params) {
  TargetScaler* s = scaler();
  if (s && params && s->storage_parameter(texture, pname, params)) return;
  real(texture, pname, params);
}

void handle_glTexParameteri(pfn_glTexParameteri real, GLenum target, GLenum pname, GLint param) {
  TargetScaler* s = scaler();
  const bool clamp = s && TargetScaler::texture_kind(target) == target && TargetScaler::level_pname(pname);
  real(target, pname, clamp ? s->texture_parameter(s->bound_texture(target), pname, param) : param);
}

void handle_glTextureParameteri(pfn_glTextureParameteri real, GLuint texture, GLenum pname, GLint param) {
  TargetScaler* s = scaler();
  real(texture, pname, s ? s->texture_parameter(texture, pname, param) : param);
}

void handle_glTexParameteriv(pfn_glTexParameteriv real, GLenum target, GLenum pname, const GLint* params) {
  TargetScaler* s = scaler();
  if (!s || TargetScaler::texture_kind(target) != target || !params || !TargetScaler::level_pname(pname))
    return real(target, pname, params);
  const GLint clamped = s->texture_parameter(s->bound_texture(target), pname, params[0]);
  if (clamped == params[0]) return real(target, pname, params);
  real(target, pname, &clamped);
}

void handle_glTextureParameteriv(pfn_glTextureParameteriv real, GLuint texture, GLenum pname, const GLint* params) {
  TargetScaler* s = scaler();
  const GLint clamped = s && params ? s->texture_parameter(texture, pname, params[0]) : 0;
  if (!s || !params || clamped == params[0]) return real(texture, pname, params);
  real(texture, pname, &clamped);
}

void handle_glRenderbufferStorage(pfn_glRenderbufferStorage real, GLenum target, GLenum internalformat, GLsizei width,
                                  GLsizei height) {
  if (TargetScaler* s = scaler(); s && width > 0 && height > 0)
    s->renderbuffer_storage(0, internalformat, &width, &height);
  real(target, internalformat, width, height);
}

void handle_glRenderbufferStorageMultisample(pfn_glRenderbufferStorageMultisample real, GLenum target, GLsizei samples,
                                             GLenum internalformat, GLsizei width, GLsizei height) {
  if (TargetScaler* s = scaler(); s && width > 0 && height > 0)
    s->renderbuffer_storage(samples, internalformat, &width, &height);
  real(target, samples, internalformat, width, height);
}

void handle_glBlitFramebuffer(pfn_glBlitFramebuffer real, GLint srcX0, GLint srcY0, GLint srcX1, GLint srcY1,
                              GLint dstX0, GLint dstY0, GLint dstX1, GLint dstY1, GLbitfield mask, GLenum filter) {
  TargetScaler* s = scaler();
  if (!s) return real(srcX0, srcY0, srcX1, srcY1, dstX0, dstY0, dstX1, dstY1, mask, filter);
  const GLint app_src[4] = {srcX0, srcY0, srcX1, srcY1}, app_dst[4] = {dstX0, dstY0, dstX1, dstY1};
  GLint src[4] = {srcX0, srcY0, srcX1, srcY1}, dst[4] = {dstX0, dstY0, dstX1, dstY1};
  s->on_blit(s->app_read_framebuffer(), s->app_draw_framebuffer());
  s->blit_rectangles(s->app_read_framebuffer(), s->app_draw_framebuffer(), src, dst);
  if (ProbeFrames* p = t_probe) p->prepare_blit();
  if (!s->blit_multisampled_window(s->app_read_framebuffer(), s->app_draw_framebuffer(), src, dst, mask, filter))
    real(src[0], src[1], src[2], src[3], dst[0], dst[1], dst[2], dst[3], mask, filter);
  if (ProbeFrames* p = t_probe) p->blit(app_src, app_dst, mask, filter);
}

void handle_glGenerateMipmap(pfn_glGenerateMipmap real, GLenum target) {
  real(target);
  if (ProbeFrames* p = t_probe; p && target == GL_TEXTURE_2D) p->generate_mipmap(0);
}

void handle_glGenerateTextureMipmap(pfn_glGenerateTextureMipmap real, GLuint texture) {
  real(texture);
  if (ProbeFrames* p = t_probe; p && texture) p->generate_mipmap(texture);
}

namespace {
// A clear of the app's (of `mask`'s buffers; `draw_buffer`: the colour buffer a glClearBuffer*
// clears, -1: all), and on probe frames the same clear of each stream's shadow.
template <typename F>
void clear_with_probes(GLbitfield mask, int draw_buffer, F&& clear) {
  if (TargetScaler* s = scaler()) s->on_clear(mask);
  ProbeFrames* p = t_probe;
  if (p) p->prepare_clear(mask, draw_buffer);
  clear();
  if (p) p->clear(clear);
}
}  // namespace

void handle_glClear(pfn_glClear real, GLbitfield mask) {
  clear_with_probes(mask, -1, [&] { real(mask); });
}

void handle_glClearBufferfv(pfn_glClearBufferfv real, GLenum buffer, GLint drawbuffer, const GLfloat* value) {
  clear_with_probes(buffer == GL_COLOR ? GL_COLOR_BUFFER_BIT : GL_DEPTH_BUFFER_BIT,
                    buffer == GL_COLOR ? drawbuffer : -1, [&] { real(buffer, drawbuffer, value); });
}

void handle_glClearBufferiv(pfn_glClearBufferiv real, GLenum buffer, GLint drawbuffer, const GLint* value) {
  clear_with_probes(buffer == GL_COLOR ? GL_COLOR_BUFFER_BIT : GL_STENCIL_BUFFER_BIT,
                    buffer == GL_COLOR ? drawbuffer : -1, [&] { real(buffer, drawbuffer, value); });
}

void handle_glClearBufferuiv(pfn_glClearBufferuiv real, GLenum buffer, GLint drawbuffer, const GLuint* value) {
  clear_with_probes(GL_COLOR_BUFFER_BIT, drawbuffer, [&] { real(buffer, drawbuffer, value); });
}

void handle_glClearBufferfi(pfn_glClearBufferfi real, GLenum buffer, GLint drawbuffer, GLfloat depth, GLint stencil) {
  clear_with_probes(GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, -1, [&] { real(buffer, drawbuffer, depth, stencil); });
}

void handle_glTextureView(pfn_glTextureView real, GLuint texture, GLenum target, GLuint origtexture,
                          GLenum internalformat, GLuint minlevel, GLuint numlevels, GLuint minlayer, GLuint numlayers) {
  if (TargetScaler* s = scaler()) s->texture_viewed(origtexture);
  real(texture, target, origtexture, internalformat, minlevel, numlevels, minlayer, numlayers);
}

void handle_glViewportIndexedf(pfn_glViewportIndexedf real, GLuint index, GLfloat x, GLfloat y, GLfloat w, GLfloat h) {
  const GLfloat box[4] = {x, y, w, h};
  TargetScaler* s = scaler();
  if (!s || !s->viewport_indexed(index, box)) real(index, x, y, w, h);
}

void handle_glViewportIndexedfv(pfn_glViewportIndexedfv real, GLuint index, const GLfloat* v) {
  TargetScaler* s = scaler();
  if (!s || !s->viewport_indexed(index, v)) real(index, v);
}

void handle_glViewportArrayv(pfn_glViewportArrayv real, GLuint first, GLsizei count, const GLfloat* v) {
  TargetScaler* s = scaler();
  if (!s || !v || count < 0) return real(first, count, v);
  for (GLsizei i = 0; i < count; ++i)
    if (!s->viewport_indexed(first + static_cast<GLuint>(i), v + 4 * i))
      real(first + static_cast<GLuint>(i), 1, v + 4 * i);
}

void handle_glScissorIndexed(pfn_glScissorIndexed real, GLuint index, GLint left, GLint bottom, GLsizei width,
                             GLsizei height) {
  const GLint box[4] = {left, bottom, width, height};
  TargetScaler* s = scaler();
  if (!s || !s->scissor_indexed(index, box)) real(index, left, bottom, width, height);
}

void handle_glScissorIndexedv(pfn_glScissorIndexedv real, GLuint index, const GLint* v) {
  TargetScaler* s = scaler();
  if (!s || !s->scissor_indexed(index, v)) real(index, v);
}

void handle_glScissorArrayv(pfn_glScissorArrayv real, GLuint first, GLsizei count, const GLint* v) {
  TargetScaler* s = scaler();
  if (!s || !v || count < 0) return real(first, count, v);
  for (GLsizei i = 0; i < count; ++i)
    if (!s->scissor_indexed(first + static_cast<GLuint>(i), v + 4 * i))
      real(first + static_cast<GLuint>(i), 1, v + 4 * i);
}

namespace {
// glGet*i_v of GL_VIEWPORT and GL_SCISSOR_BOX: the app's boxes, as glGet* answers index 0's.
template <typename T>
void answer_indexed_for_app(GLenum target, GLuint index, T* data) {
  TargetScaler* s = scaler();
  if (!s || !data) return;
  if (target == GL_VIEWPORT) {
    GLfloat box[4];
    if (s->app_viewport_at(index, box))
      for (int i = 0; i < 4; ++i) data[i] = static_cast<T>(box[i]);
  } else if (target == GL_SCISSOR_BOX) {
    GLint box[4];
    if (s->app_scissor_at(index, box))
      for (int i = 0; i < 4; ++i) data[i] = static_cast<T>(box[i]);
  }
}
}  // namespace

void handle_glGetFloati_v(pfn_glGetFloati_v real, GLenum target, GLuint index, GLfloat* data) {
  real(target, index, data);
  answer_indexed_for_app(target, index, data);
}
void handle_glGetDoublei_v(pfn_glGetDoublei_v real, GLenum target, GLuint index, GLdouble* data) {
  real(target, index, data);
  answer_indexed_for_app(target, index, data);
}
void handle_glGetIntegeri_v(pfn_glGetIntegeri_v real, GLenum target, GLuint index, GLint* data) {
  real(target, index, data);
  answer_indexed_for_app(target, index, data);
}
void handle_glGetInteger64i_v(pfn_glGetInteger64i_v real, GLenum target, GLuint index, GLint64* data) {
  real(target, index, data);
  answer_indexed_for_app(target, index, data);
}

void handle_glPushAttrib(pfn_glPushAttrib real, GLbitfield mask) {
  real(mask);
  if (TargetScaler* s = scaler()) s->attrib_pushed(mask);
}

void handle_glPopAttrib(pfn_glPopAttrib real) {
  TargetScaler* s = scaler();
  if (!s) return real();
  s->pop_attrib(real);
}

void handle_glReadPixels(pfn_glReadPixels real, GLint x, GLint y, GLsizei width, GLsizei height, GLenum format,
                         GLenum type, void* pixels) {
  TargetScaler* s = scaler();
  if (!s) return real(x, y, width, height, format, type, pixels);
  const bool depth_stencil = format == GL_DEPTH_COMPONENT || format == GL_DEPTH_STENCIL || format == GL_STENCIL_INDEX;
  s->read_app(x, y, width, height, depth_stencil, [&] { real(x, y, width, height, format, type, pixels); });
}

void handle_glCopyTexImage2D(pfn_glCopyTexImage2D real, GLenum target, GLint level, GLenum internalformat, GLint x,
                             GLint y, GLsizei width, GLsizei height, GLint border) {
  TargetScaler* s = scaler();
  if (!s) return real(target, level, internalformat, x, y, width, height, border);
  const bool depth = TargetScaler::depth_format(static_cast<GLint>(internalformat));
  s->read_app(x, y, width, height, depth, [&] { real(target, level, internalformat, x, y, width, height, border); });
}

void handle_glCopyTexSubImage2D(pfn_glCopyTexSubImage2D real, GLenum target, GLint level, GLint xoffset, GLint yoffset,
                                GLint x, GLint y, GLsizei width, GLsizei height) {
  TargetScaler* s = scaler();
  if (!s) return real(target, level, xoffset, yoffset, x, y, width, height);
  // Depth or colour as the texture copied into is (known where the scaler tracks it).
  const bool depth = s->active() && s->depth_texture(s->bound_texture(target));
  s->read_app(x, y, width, height, depth, [&] { real(target, level, xoffset, yoffset, x, y, width, height); });
}

namespace {
bool window_bound(const TargetScaler* s, bool read) {
  return s && s->window_scaled() && (read ? s->app_read_framebuffer() : s->app_draw_framebuffer()) == 0;
}

// Default-framebuffer attachment names (GL_COLOR, GL_DEPTH, GL_STENCIL) as the stand-in's.
std::vector<GLenum> stand_in_attachments(GLsizei n, const GLenum* attachments) {
  std::vector<GLenum> out(attachments, attachments + (n > 0 ? n : 0));
  for (GLenum& a : out) {
    if (a == GL_COLOR || a == GL_BACK_LEFT || a == GL_BACK)
      a = GL_COLOR_ATTACHMENT0;
    else if (a == GL_DEPTH)
      a = GL_DEPTH_ATTACHMENT;
    else if (a == GL_STENCIL)
      a = GL_STENCIL_ATTACHMENT;
  }
  return out;
}
}  // namespace

void handle_glDrawBuffer(pfn_glDrawBuffer real, GLenum buf) {
  TargetScaler* s = scaler();
  real(window_bound(s, false) ? TargetScaler::window_buffer(buf) : buf);
}

void handle_glDrawBuffers(pfn_glDrawBuffers real, GLsizei n, const GLenum* bufs) {
  TargetScaler* s = scaler();
  if (!window_bound(s, false) || n <= 0 || !bufs) return real(n, bufs);
  std::vector<GLenum> mapped(bufs, bufs + n);
  for (GLenum& b : mapped) b = TargetScaler::window_buffer(b);
  real(n, mapped.data());
}

void handle_glReadBuffer(pfn_glReadBuffer real, GLenum src) {
  TargetScaler* s = scaler();
  real(window_bound(s, true) ? TargetScaler::window_buffer(src) : src);
}

void handle_glInvalidateFramebuffer(pfn_glInvalidateFramebuffer real, GLenum target, GLsizei n,
                                    const GLenum* attachments) {
  TargetScaler* s = scaler();
  if (!window_bound(s, target == GL_READ_FRAMEBUFFER) || !attachments) return real(target, n, attachments);
  const std::vector<GLenum> mapped = stand_in_attachments(n, attachments);
  real(target, n, mapped.data());
}

void handle_glInvalidateSubFramebuffer(pfn_glInvalidateSubFramebuffer real, GLenum target, GLsizei n,
                                       const GLenum* attachments, GLint x, GLint y, GLsizei width, GLsizei height) {
  TargetScaler* s = scaler();
  if (!window_bound(s, target == GL_READ_FRAMEBUFFER) || !attachments)
    return real(target, n, attachments, x, y, width, height);
  const std::vector<GLenum> mapped = stand_in_attachments(n, attachments);
  real(target, n, mapped.data(), x, y, width, height);  // a hint: the region may be larger
}

void handle_glDiscardFramebufferEXT(pfn_glDiscardFramebufferEXT real, GLenum target, GLsizei n,
                                    const GLenum* attachments) {
  TargetScaler* s = scaler();
  if (!window_bound(s, false) || !attachments) return real(target, n, attachments);
  const std::vector<GLenum> mapped = stand_in_attachments(n, attachments);
  real(target, n, mapped.data());
}

// Questions about the window's attachments are answered by the window itself.
void handle_glGetFramebufferAttachmentParameteriv(pfn_glGetFramebufferAttachmentParameteriv real, GLenum target,
                                                  GLenum attachment, GLenum pname, GLint* params) {
  TargetScaler* s = scaler();
  const bool read = target == GL_READ_FRAMEBUFFER;
  if (!window_bound(s, read)) return real(target, attachment, pname, params);
  static const auto bind = reinterpret_cast<pfn_glBindFramebuffer>(resolve_real(kHook_glBindFramebuffer));
  bind(target, 0);
  real(target, attachment, pname, params);
  bind(target, s->real_framebuffer(0));
}

void handle_glBlitNamedFramebuffer(pfn_glBlitNamedFramebuffer real, GLuint readFramebuffer, GLuint drawFramebuffer,
                                   GLint srcX0, GLint srcY0, GLint srcX1, GLint srcY1, GLint dstX0, GLint dstY0,
                                   GLint dstX1, GLint dstY1, GLbitfield mask, GLenum filter) {
  TargetScaler* s = scaler();
  if (!s)
    return real(readFramebuffer, drawFramebuffer, srcX0, srcY0, srcX1, srcY1, dstX0, dstY0, dstX1, dstY1, mask, filter);
  GLint src[4] = {srcX0, srcY0, srcX1, srcY1}, dst[4] = {dstX0, dstY0, dstX1, dstY1};
  s->on_blit(readFramebuffer, drawFramebuffer);
  s->blit_rectangles(readFramebuffer, drawFramebuffer, src, dst);
  if (s->blit_multisampled_window(readFramebuffer, drawFramebuffer, src, dst, mask, filter)) return;
  real(s->real_framebuffer(readFramebuffer), s->real_framebuffer(drawFramebuffer), src[0], src[1], src[2], src[3],
       dst[0], dst[1], dst[2], dst[3], mask, filter);
}

void handle_glNamedFramebufferDrawBuffer(pfn_glNamedFramebufferDrawBuffer real, GLuint framebuffer, GLenum buf) {
  TargetScaler* s = scaler();
  if (framebuffer || !s || !s->window_scaled()) return real(framebuffer, buf);
  real(s->real_framebuffer(0), TargetScaler::window_buffer(buf));
}

void handle_glNamedFramebufferDrawBuffers(pfn_glNamedFramebufferDrawBuffers real, GLuint framebuffer, GLsizei n,
                                          const GLenum* bufs) {
  TargetScaler* s = scaler();
  if (framebuffer || !s || !s->window_scaled() || n <= 0 || !bufs) return real(framebuffer, n, bufs);
  std::vector<GLenum> mapped(bufs, bufs + n);
  for (GLenum& b : mapped) b = TargetScaler::window_buffer(b);
  real(s->real_framebuffer(0), n, mapped.data());
}

void handle_glNamedFramebufferReadBuffer(pfn_glNamedFramebufferReadBuffer real, GLuint framebuffer, GLenum src) {
  TargetScaler* s = scaler();
  if (framebuffer || !s || !s->window_scaled()) return real(framebuffer, src);
  real(s->real_framebuffer(0), TargetScaler::window_buffer(src));
}

namespace {
GLuint named(GLuint framebuffer) {
  TargetScaler* s = scaler();
  return framebuffer == 0 && s ? s->real_framebuffer(0) : framebuffer;
}
}  // namespace

void handle_glClearNamedFramebufferiv(pfn_glClearNamedFramebufferiv real, GLuint framebuffer, GLenum buffer,
                                      GLint drawbuffer, const GLint* value) {
  real(named(framebuffer), buffer, drawbuffer, value);
}
void handle_glClearNamedFramebufferuiv(pfn_glClearNamedFramebufferuiv real, GLuint framebuffer, GLenum buffer,
                                       GLint drawbuffer, const GLuint* value) {
  real(named(framebuffer), buffer, drawbuffer, value);
}
void handle_glClearNamedFramebufferfv(pfn_glClearNamedFramebufferfv real, GLuint framebuffer, GLenum buffer,
                                      GLint drawbuffer, const GLfloat* value) {
  real(named(framebuffer), buffer, drawbuffer, value);
}
void handle_glClearNamedFramebufferfi(pfn_glClearNamedFramebufferfi real, GLuint framebuffer, GLenum buffer,
                                      GLint drawbuffer, GLfloat depth, GLint stencil) {
  real(named(framebuffer), buffer, drawbuffer, depth, stencil);
}

namespace {
// A target glGetTexLevelParameter takes of a texture the scaler may store at another size: a
// cube map by its faces.
bool level_target(GLenum target) { return TargetScaler::texture_kind(target) != 0 && target != GL_TEXTURE_CUBE_MAP; }
}  // namespace

void handle_glGetTexLevelParameteriv(pfn_glGetTexLevelParameteriv real, GLenum target, GLint level, GLenum pname,
                                     GLint* params) {
  real(target, level, pname, params);
  if (TargetScaler* s = scaler(); s && level_target(target) && params && TargetScaler::size_pname(pname))
    s->texture_size(s->bound_texture(target), level, pname, params);
}

void handle_glGetTextureLevelParameteriv(pfn_glGetTextureLevelParameteriv real, GLuint texture, GLint level,
                                         GLenum pname, GLint* params) {
  real(texture, level, pname, params);
  if (TargetScaler* s = scaler(); s && params) s->texture_size(texture, level, pname, params);
}

void handle_glGetTextureLevelParameterfv(pfn_glGetTextureLevelParameterfv real, GLuint texture, GLint level,
                                         GLenum pname, GLfloat* params) {
  real(texture, level, pname, params);
  GLint v = 0;
  if (TargetScaler* s = scaler(); s && params && s->texture_size(texture, level, pname, &v))
    *params = static_cast<GLfloat>(v);
}

void handle_glGetTexLevelParameterfv(pfn_glGetTexLevelParameterfv real, GLenum target, GLint level, GLenum pname,
                                     GLfloat* params) {
  real(target, level, pname, params);
  GLint v = 0;
  if (TargetScaler* s = scaler(); s && level_target(target) && params && TargetScaler::size_pname(pname) &&
                                  s->texture_size(s->bound_texture(target), level, pname, &v))
    *params = static_cast<GLfloat>(v);
}

void handle_glGetRenderbufferParameteriv(pfn_glGetRenderbufferParameteriv real, GLenum target, GLenum pname,
                                         GLint* params) {
  real(target, pname, params);
  if (TargetScaler* s = scaler(); s && params) s->renderbuffer_size(pname, params);
}

}  // namespace glbudget

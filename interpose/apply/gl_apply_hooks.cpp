// The app's calls that meet render-target scaling and program shadowing: framebuffer and image
// life cycle, viewport and scissor, blits, and the queries that must answer for the app.
#include <algorithm>

#include "context_state.h"
#include "hooks_generated.h"
#include "hook_table.h"
#include "render_targets.h"

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
  if (pname == GL_CURRENT_PROGRAM && c->bound_variants) {
    params[0] = static_cast<T>(c->program);
  } else if ((pname == GL_VIEWPORT || pname == GL_SCISSOR_BOX) && c->targets && c->targets->active()) {
    const GLint* box = pname == GL_VIEWPORT ? c->targets->app_viewport() : c->targets->app_scissor();
    for (int i = 0; i < 4; ++i) params[i] = static_cast<T>(box[i]);
  }
}
}  // namespace

void handle_glGetIntegerv(pfn_glGetIntegerv real, GLenum pname, GLint* data) {
  real(pname, data);
  answer_for_app(pname, data);
}
void handle_glGetInteger64v(pfn_glGetInteger64v real, GLenum pname, GLint64* data) {
  real(pname, data);
  answer_for_app(pname, data);
}
void handle_glGetFloatv(pfn_glGetFloatv real, GLenum pname, GLfloat* data) {
  real(pname, data);
  answer_for_app(pname, data);
}
void handle_glGetDoublev(pfn_glGetDoublev real, GLenum pname, GLdouble* data) {
  real(pname, data);
  answer_for_app(pname, data);
}
void handle_glGetBooleanv(pfn_glGetBooleanv real, GLenum pname, GLboolean* data) {
  real(pname, data);
  if (pname == GL_CURRENT_PROGRAM) answer_for_app(pname, data);  // boxes as booleans mean nothing
}

void handle_glBindFramebuffer(pfn_glBindFramebuffer real, GLenum target, GLuint framebuffer) {
  real(target, framebuffer);
  ContextState* c = current_context();
  if (!c || !c->targets) return;
  c->targets->bind_framebuffer(target, framebuffer);
  if (target != GL_READ_FRAMEBUFFER) c->counter->invalidate();  // the next draw may reveal a target
}

void handle_glFramebufferTexture2D(pfn_glFramebufferTexture2D real, GLenum target, GLenum attachment,
                                   GLenum textarget, GLuint texture, GLint level) {
  real(target, attachment, textarget, texture, level);
  if (TargetScaler* s = scaler()) s->framebuffer_attachment_changed(target);
}

void handle_glFramebufferTexture(pfn_glFramebufferTexture real, GLenum target, GLenum attachment, GLuint texture,
                                 GLint level) {
  real(target, attachment, texture, level);
  if (TargetScaler* s = scaler()) s->framebuffer_attachment_changed(target);
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

void handle_glTexImage2D(pfn_glTexImage2D real, GLenum target, GLint level, GLint internalformat, GLsizei width,
                         GLsizei height, GLint border, GLenum format, GLenum type, const void* pixels) {
  TargetScaler* s = scaler();
  if (s && target == GL_TEXTURE_2D && width > 0 && height > 0) {
    GLint unpack = 0;
    // With an unpack buffer bound, `pixels` is an offset into it: data all the same.
    static const auto get = reinterpret_cast<pfn_glGetIntegerv>(resolve_real(kHook_glGetIntegerv));
    if (get) get(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack);
    s->tex_image_2d(level, internalformat, &width, &height, format, type, pixels != nullptr || unpack != 0);
  }
  real(target, level, internalformat, width, height, border, format, type, pixels);
}

void handle_glRenderbufferStorage(pfn_glRenderbufferStorage real, GLenum target, GLenum internalformat,
                                  GLsizei width, GLsizei height) {
  if (TargetScaler* s = scaler(); s && width > 0 && height > 0) s->renderbuffer_storage(0, internalformat, &width, &height);
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
  GLint src[4] = {srcX0, srcY0, srcX1, srcY1}, dst[4] = {dstX0, dstY0, dstX1, dstY1};
  s->blit_rectangles(src, dst);
  real(src[0], src[1], src[2], src[3], dst[0], dst[1], dst[2], dst[3], mask, filter);
}

void handle_glGetTexLevelParameteriv(pfn_glGetTexLevelParameteriv real, GLenum target, GLint level, GLenum pname,
                                     GLint* params) {
  real(target, level, pname, params);
  if (TargetScaler* s = scaler(); s && target == GL_TEXTURE_2D && params) s->texture_size(level, pname, params);
}

void handle_glGetTexLevelParameterfv(pfn_glGetTexLevelParameterfv real, GLenum target, GLint level, GLenum pname,
                                     GLfloat* params) {
  real(target, level, pname, params);
  GLint v = 0;
  if (TargetScaler* s = scaler(); s && target == GL_TEXTURE_2D && params && s->texture_size(level, pname, &v))
    *params = static_cast<GLfloat>(v);
}

void handle_glGetRenderbufferParameteriv(pfn_glGetRenderbufferParameteriv real, GLenum target, GLenum pname,
                                         GLint* params) {
  real(target, pname, params);
  if (TargetScaler* s = scaler(); s && params) s->renderbuffer_size(pname, params);
}

}  // namespace glbudget

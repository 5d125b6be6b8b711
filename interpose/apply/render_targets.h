// Render-target scaling: the textures and renderbuffers of the framebuffers a level scales are
// stored at the scaled size, all attachments of a framebuffer together, while the app keeps
// its names and sees its own sizes. Viewport and scissor are scaled while a scaled framebuffer
// is bound, blit rectangles by their framebuffers' scales; size and viewport queries answer
// the app's values. A framebuffer is a target of a pass once a draw of that pass went to it;
// when its scale changes (then, or at a swap that switches configuration) its images are
// respecified and their contents carried over by a blit.
// Limits: 2D textures and renderbuffers (not immutable textures, arrays, cube maps); textures
// are tracked per context; the default framebuffer is scaled elsewhere.
#pragma once
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "configuration.h"
#include "gl_types.h"

namespace glbudget {

class TargetScaler {
 public:
  TargetScaler();  // reads the viewport and scissor the context starts with

  // The configuration in force; re-scales the framebuffers seen so far.
  void set_configuration(const Levels& config);
  // A draw is about to go to the bound draw framebuffer under manifest pass `pass` (-1: none).
  void on_draw(int pass);

  // Hooks. Each returns what the real call must be given, or handles the call itself.
  void bind_framebuffer(GLenum target, GLuint fbo);
  void framebuffer_attachment_changed(GLenum target);
  void framebuffers_deleted(GLsizei n, const GLuint* names);
  void textures_deleted(GLsizei n, const GLuint* names);
  void renderbuffers_deleted(GLsizei n, const GLuint* names);
  void viewport(GLint x, GLint y, GLsizei w, GLsizei h);
  void scissor(GLint x, GLint y, GLsizei w, GLsizei h);
  // glTexImage2D of the texture bound to GL_TEXTURE_2D: fills the size to give the driver.
  void tex_image_2d(GLint level, GLint internal_format, GLsizei* width, GLsizei* height, GLenum format,
                    GLenum type, bool with_data);
  void renderbuffer_storage(GLsizei samples, GLenum internal_format, GLsizei* width, GLsizei* height);
  void blit_rectangles(GLint* src, GLint* dst) const;  // x0, y0, x1, y1 each
  // The app's size for a scaled image (GL_TEXTURE_WIDTH/HEIGHT, GL_RENDERBUFFER_WIDTH/HEIGHT).
  bool texture_size(GLint level, GLenum pname, GLint* value) const;
  bool renderbuffer_size(GLenum pname, GLint* value) const;
  // The app's viewport and scissor box (4 values) for glGet*.
  const GLint* app_viewport() const { return viewport_.data(); }
  const GLint* app_scissor() const { return scissor_.data(); }
  bool active() const { return any_scaled_; }

 private:
  struct Image {
    bool renderbuffer = false;
    GLint internal_format = 0;
    GLenum format = 0, type = 0;
    GLsizei samples = 0;
    std::vector<std::array<GLsizei, 2>> app_size;  // per mip level the app specified
    double scale = 1.0;                            // applied
    GLsizei stored_width() const;
    GLsizei stored_height() const;
  };
  struct Attachment {
    GLenum point = 0;
    bool renderbuffer = false;
    GLuint name = 0;
  };
  struct Framebuffer {
    std::vector<Attachment> attachments;
    bool attachments_known = false;
    uint64_t passes = 0;  // bit per manifest pass whose draws went here
    double scale = 1.0;
  };

  double wanted_scale(GLuint name, const Framebuffer& f) const;
  void learn_attachments(Framebuffer& f);
  void ensure_scale(GLuint name, Framebuffer& f);
  void rescale(GLuint name, Image& image, double scale);
  void apply_viewport();
  void scale_of(GLuint fbo, double* sx, double* sy) const;

  Levels config_;
  std::unordered_map<GLuint, Image> textures_, renderbuffers_;
  std::unordered_map<GLuint, Framebuffer> framebuffers_;
  GLuint draw_fbo_ = 0, read_fbo_ = 0;
  std::array<GLint, 4> viewport_{}, scissor_{};
  bool any_scaled_ = false;
};

}  // namespace glbudget

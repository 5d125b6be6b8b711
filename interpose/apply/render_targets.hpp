// Render-target scaling: the textures and renderbuffers of the framebuffers a level scales are
// stored at the scaled size, all attachments of a framebuffer together, while the app keeps
// its names and sees its own sizes. Viewport and scissor are scaled while a scaled framebuffer
// is bound, blit rectangles by their framebuffers' scales; size and viewport queries answer
// the app's values. A framebuffer is a target of a pass once a draw of that pass went to it;
// when its scale changes (then, or at a swap that switches configuration) its images are
// respecified and their contents carried over by a blit.
// The default framebuffer (the window) is scaled the way Proton's fullscreen hack resizes it:
// a stand-in framebuffer at the scaled size takes its place whenever the app binds 0, and is
// drawn into the real back buffer at each swap. Reads of the window (glReadPixels,
// glCopyTex*) see a window-sized image, binding queries answer 0.
// A multisampled window gets a stand-in of as many samples, resolved and stretched at the swap.
// Textures of the four kinds a framebuffer draws into a layer or face of (2D, 2D arrays, cube
// maps, cube-map arrays: cascaded and point-light shadow maps) scale alike, every layer and
// face together; so do multisample 2D textures (MSAA scene targets), desktop GL only.
// Limits: not immutable textures of a format no framebuffer holds, nor mipmapped immutable
// ones but of the window's size or named by the manifest; not 3D or multisample array textures; a
// framebuffer with an image the scaler cannot scale keeps its size; textures are tracked per
// context; a multisampled GLES window is not scaled.
// A context with framebuffer objects but no blits (OpenGL ES 2.0) scales the window alone: its
// stand-in's colour is a texture, presented and read back by drawing it (draw_copy.hpp); the
// app's own framebuffers keep their sizes there (window_without_blits.cpp).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <set>
#include <unordered_map>
#include <vector>

#include "configuration.hpp"
#include "draw_copy.hpp"
#include "gl_types.hpp"
#include "pass_counter.hpp"

namespace glbudget {

// A viewport or scissor box (x, y, width, height) scaled by its edges, as the driver is given it.
void scale_box(const GLint* in, double sx, double sy, GLint* out);
// A blit rectangle's corners (x0, y0, x1, y1) scaled; `out` may be `in`.
void scale_corners(const GLint* in, double sx, double sy, GLint* out);
// The sized format of an unsized colour format (GL_RGBA: GL_RGBA8, as drivers size it), for
// storage that takes sized formats only; other formats as they are.
GLint sized_internal_format(GLint format);
// Attaches level 0 of `texture`, of kind `kind` (TargetScaler::texture_kind), to `point` of the
// framebuffer bound to `target`: a 2D or multisample texture whole, a cube map's face `layer`,
// an array's layer `layer`.
void attach_texture_layer(GLenum target, GLenum point, GLenum kind, GLuint texture, GLint layer);
// The levels of a full mip chain of a width x height level 0 (1 + log2 of the larger side).
int full_mip_levels(int width, int height);

class TargetScaler {
 public:
  // Reads the viewport and scissor the context starts with (current, of `caps`).
  explicit TargetScaler(const GlCaps& caps);
  // glBlitFramebuffer and separate read and draw bindings (GL 3.0, GLES 3.0, or desktop GL 2.x
  // with ARB_framebuffer_object); without them the window alone is scaled (GLES 2.0).
  static bool has_blits(const GlCaps& caps) { return caps.framebuffer_blit; }
  bool blits() const { return has_blits(caps_); }

  // The configuration in force; re-scales the framebuffers seen so far.
  void set_configuration(const Levels& config);
  // A draw is about to go to the bound draw framebuffer under manifest pass `pass` (-1: none).
  void on_draw(int pass);
  // Before a blit between the app's framebuffers `read` and `draw` (0: the window): a
  // framebuffer first met there (a multisampled scene resolved into one no draw reaches) is
  // learnt and scaled as a draw would, so that both rectangles scale alike.
  void on_blit(GLuint read, GLuint draw);
  // glClear / glClearBuffer* of the bound draw framebuffer (mask: GL_*_BUFFER_BIT).
  void on_clear(GLbitfield mask);
  void end_frame() { ++frame_; }

  // The window's size, as the window system says (at make-current and at each swap).
  void set_window_size(int width, int height);
  // Before the real swap: the stand-in drawn into the back buffer.
  void present();
  // The name the driver must get for the app's framebuffer name (the stand-in for 0).
  GLuint real_framebuffer(GLuint app) const { return app == 0 && window_.fbo ? window_.fbo : app; }
  bool window_scaled() const { return window_.fbo != 0; }
  // The window's samples (0: single-sampled), asked of the driver once.
  int window_samples();
  // The window's own depth and stencil (0 bits: none), asked of the driver once.
  struct DepthStencil {
    int depth_bits = 0, stencil_bits = 0;
    bool floating_depth = false;
  };
  const DepthStencil& window_depth_stencil();
  GLuint app_draw_framebuffer() const { return draw_fbo_; }
  GLuint app_read_framebuffer() const { return read_fbo_; }
  // Runs `read` (a glReadPixels or glCopyTex* of the app, of the rectangle x, y, w, h in its
  // own pixels; `depth_stencil`: of depth or stencil) so that it reads the app's sizes: the
  // window through a window-sized copy of the stand-in, a scaled app framebuffer through an
  // app-sized copy of the rectangle (nearest texels, so that an object id read under the
  // cursor stays an id), else as it is.
  template <typename F>
  void read_app(GLint x, GLint y, GLsizei w, GLsizei h, bool depth_stencil, F&& read) {
    if (read_fbo_ == 0) {
      if (!window_.fbo) return read();
      bind_window_copy();
      read();
      unbind_window_copy();
      return;
    }
    if (!any_scaled_ || !bind_read_copy(x, y, w, h, depth_stencil)) return read();
    read();
    agl_bind_read_framebuffer(read_fbo_);
  }
  // glPushAttrib/glPopAttrib (compatibility profile, SFML's pushGLStates, fixed-function HUDs):
  // GL's stack restores the driver's viewport and scissor box, which are scaled, so the app's
  // are kept on a stack of the same depth and given again after the pop, scaled for the
  // framebuffer bound then (a push before a swap that switched the scale, popped after it).
  void attrib_pushed(GLbitfield mask);
  // The app's glPopAttrib (`pop`, the real call) and then attrib_popped. Draw and read buffers
  // pushed with the window bound name the window as it was then, GL_BACK or the stand-in's
  // GL_COLOR_ATTACHMENT0: where a swap has switched its scale since (a governor's transition),
  // the driver would reject them on what the window is now. They are popped onto a framebuffer
  // of the kind they name, and the window given their equivalent.
  void pop_attrib(void (*pop)());
  void attrib_popped();
  // glDrawBuffer(s)/glReadBuffer of the window while the stand-in is bound: GL_BACK and the
  // like become GL_COLOR_ATTACHMENT0.
  static GLenum window_buffer(GLenum buffer);

  // Hooks. Each returns what the real call must be given, or handles the call itself.
  void bind_framebuffer(GLenum target, GLuint fbo);
  void framebuffer_attachment_changed(GLenum target);
  // The same by name (glNamedFramebufferTexture*, glNamedFramebufferRenderbuffer).
  void named_framebuffer_attachment_changed(GLuint framebuffer);
  // Counts the app's attachment changes to any framebuffer: quality probes describe a
  // framebuffer again when it moved (a shadow renderer re-attaching layer after layer).
  uint64_t attachment_changes() const { return attachment_changes_; }
  void framebuffers_deleted(GLsizei n, const GLuint* names);
  void textures_deleted(GLsizei n, const GLuint* names);
  void renderbuffers_deleted(GLsizei n, const GLuint* names);
  void viewport(GLint x, GLint y, GLsizei w, GLsizei h);
  void scissor(GLint x, GLint y, GLsizei w, GLsizei h);
  // Viewport arrays (GL 4.1, ARB_viewport_array; Wine's wined3d sets its viewport and scissor
  // this way): the app's box at `index` kept and given scaled, as glViewport's and glScissor's
  // are; false where the call is not the scaler's to make (an index or size the driver refuses,
  // no viewport arrays): the hook passes it on as it is.
  bool viewport_indexed(GLuint index, const GLfloat* box);
  bool scissor_indexed(GLuint index, const GLint* box);
  // The app's box at `index` for glGet*i_v (false: the driver's answer stands).
  bool app_viewport_at(GLuint index, GLfloat* box) const;
  bool app_scissor_at(GLuint index, GLint* box) const;
  // The texture kinds scaled here (GL_TEXTURE_2D, _2D_ARRAY, _CUBE_MAP, _CUBE_MAP_ARRAY), and
  // the kind a call's target specifies (a cube map's face: GL_TEXTURE_CUBE_MAP); 0 for others.
  static GLenum texture_kind(GLenum target);
  // The binding query of a kind (GL_TEXTURE_BINDING_2D_ARRAY for GL_TEXTURE_2D_ARRAY, ...).
  static GLenum binding_of(GLenum kind);
  // glTexImage2D (GL_TEXTURE_2D, a cube map's face) or glTexImage3D (a 2D or cube-map array,
  // `layers` deep) of the texture bound to the call's target: fills the size to give the driver.
  void tex_image(GLenum target, GLint level, GLint internal_format, GLsizei* width, GLsizei* height, GLsizei layers,
                 GLenum format, GLenum type, bool with_data);
  // glTex(ture)Storage2D/3D of a texture of a kind above. Immutable storage cannot be
  // respecified at another size, so storage of a format a framebuffer can hold is made as
  // mutable storage of that format instead, every level the app asked for, its levels clamped
  // to those (as an immutable texture clamps them), and scales as glTexImage2D's do; true where
  // it was made here. Several levels only for a texture of the window's size (a render target's
  // mip chain) or one a manifest names: other mipmapped textures are the app's assets, left
  // immutable (glTextureView needs that).
  // `texture` is the one bound to `kind` (bound_texture(kind)), or one named by
  // glTextureStorage2D/3D (bound for the call and restored); `layers`: an array's depth, else 1.
  bool tex_storage(GLenum kind, GLuint texture, GLsizei levels, GLenum internal_format, GLsizei width, GLsizei height,
                   GLsizei layers);
  // glGet(Tex|Texture)Parameter of such a texture: GL_TEXTURE_IMMUTABLE_FORMAT,
  // GL_TEXTURE_IMMUTABLE_LEVELS, GL_TEXTURE_BASE_LEVEL and GL_TEXTURE_MAX_LEVEL as the app made
  // and set them; false for other textures and names.
  bool storage_parameter(GLuint texture, GLenum pname, GLint* value) const;
  // gl(Tex|Texture)Parameter: what the driver gets. Such a texture's base and maximum levels
  // are kept as the app sets them and given clamped to its levels.
  GLint texture_parameter(GLuint texture, GLenum pname, GLint value);
  // glTexImage2DMultisample of the texture bound to GL_TEXTURE_2D_MULTISAMPLE: fills the size
  // to give the driver.
  void tex_image_multisample(GLsizei samples, GLenum internal_format, GLsizei* width, GLsizei* height,
                             GLboolean fixed_locations);
  // glTex(ture)Storage2DMultisample: made mutable (glTexImage2DMultisample) where the driver
  // has it (desktop GL 3.2+), so that it can be resized, and answered as immutable; true
  // where it was made here.
  bool tex_storage_multisample(GLuint texture, GLsizei samples, GLenum internal_format, GLsizei width, GLsizei height,
                               GLboolean fixed_locations);
  // The texture bound to a call's target (a face: the cube map) on the active unit.
  GLuint bound_texture(GLenum target) const;
  // Before glTextureView of `texture`: a view needs immutable storage, so storage made mutable
  // here (tex_storage) becomes the driver's immutable storage at the app's size, its contents
  // kept, and is never scaled again, nor are the framebuffers it is attached to (said once).
  void texture_viewed(GLuint texture);
  // The pnames the three above answer or clamp: the hooks ask for the binding only for these.
  static bool level_pname(GLenum pname) { return pname == GL_TEXTURE_BASE_LEVEL || pname == GL_TEXTURE_MAX_LEVEL; }
  static bool storage_pname(GLenum pname) {
    return pname == GL_TEXTURE_IMMUTABLE_FORMAT || pname == GL_TEXTURE_IMMUTABLE_LEVELS || level_pname(pname);
  }
  static bool size_pname(GLenum pname) { return pname == GL_TEXTURE_WIDTH || pname == GL_TEXTURE_HEIGHT; }
  // A depth, depth-stencil or stencil internal format; a 2D texture the scaler knows made of one.
  static bool depth_format(GLint format);
  bool depth_texture(GLuint texture) const;
  // The kind (texture_kind) of a texture the scaler saw specified; 0 for one it did not.
  GLenum kind_of(GLuint texture) const;
  void renderbuffer_storage(GLsizei samples, GLenum internal_format, GLsizei* width, GLsizei* height);
  // x0, y0, x1, y1 each, by the scales of the app's framebuffers `read` and `draw`.
  void blit_rectangles(GLuint read, GLuint draw, GLint* src, GLint* dst) const;
  // A blit (rectangles scaled already) between an app framebuffer and a multisampled window's
  // stand-in whose rectangles differ in size, which a multisampled framebuffer does not take:
  // done here through the single-sampled resolve image; false where the driver can take it.
  bool blit_multisampled_window(GLuint read, GLuint draw, const GLint* src, const GLint* dst, GLbitfield mask,
                                GLenum filter);
  // The app's size for a scaled image (GL_TEXTURE_WIDTH/HEIGHT, GL_RENDERBUFFER_WIDTH/HEIGHT):
  // the texture bound to GL_TEXTURE_2D, or one named (glGetTextureLevelParameter).
  bool texture_size(GLuint texture, GLint level, GLenum pname, GLint* value) const;
  bool renderbuffer_size(GLenum pname, GLint* value) const;
  // The app's size of level 0 of a 2D texture the scaler knows, and whether it is stored at
  // another size now; false for a texture it does not know (stored as the app made it).
  bool app_texture_size(GLuint texture, GLint* width, GLint* height, bool* scaled) const;
  // The 2D texture bound to texture unit `unit` (0 for a unit the driver does not have).
  GLuint texture_at_unit(GLint unit);
  // The app's viewport and scissor box (4 values) for glGet*.
  const GLint* app_viewport() const { return viewport_.data(); }
  const GLint* app_scissor() const { return scissor_.data(); }
  bool active() const { return any_scaled_; }
  // The driver's viewport and scissor boxes may be scaled (an app framebuffer or the window is):
  // glGet* and glGet*i_v answer the app's.
  bool boxes_scaled() const { return any_scaled_ || window_scaled(); }

  // For quality probes (apply/probes.hpp): the scale `config` would give the app's framebuffer
  // (0: the window), the scale its images are stored at now, and the window's size.
  double scale_for(GLuint app_fbo, const Levels& config) const;
  void stored_scale(GLuint app_fbo, double* sx, double* sy) const { scale_of(app_fbo, sx, sy); }
  // Whether the app's images of its framebuffer (0: the window) are stored at `scale` now.
  bool stored_at(GLuint app_fbo, double scale) const;
  int window_width() const { return window_width_; }
  int window_height() const { return window_height_; }

 private:
  struct Image {
    bool renderbuffer = false;
    GLenum kind = GL_TEXTURE_2D;  // of a texture: texture_kind()
    GLsizei layers = 1;           // of an array: its depth (a cube-map array's: 6 per cube)
    GLint internal_format = 0;
    GLenum format = 0, type = 0;
    GLsizei samples = 0;
    GLboolean fixed_locations = GL_TRUE;             // of a multisample texture
    GLsizei storage_levels = 0;                      // made by glTexStorage2D (stored mutable): its levels
    GLint app_base_level = 0, app_max_level = 1000;  // of such a texture, as the app set them
    std::vector<std::array<GLsizei, 2>> app_size;    // per mip level the app specified
    double scale = 1.0;                              // applied
    GLsizei stored_width() const;
    GLsizei stored_height() const;
    // A level's stored size: a full mip chain's levels halve the stored level 0, so that the
    // texture stays complete at any scale; other levels scale on their own.
    std::array<GLsizei, 2> stored_level_size(size_t level) const;
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
    // Frame numbers of the first draw here, and of a clear of every buffer before it: a
    // framebuffer cleared whole before it is drawn each frame needs no contents carried over
    // when a switch rescales it at a swap.
    uint64_t drawn_frame = 0, cleared_frame = 0;
    GLbitfield cleared = 0;
    double scale = 1.0;
  };

  // A framebuffer of single-sampled renderbuffers in the window's formats (the colour a
  // texture where there are no blits, so that it can be drawn).
  struct ImageSet {
    GLuint fbo = 0, color = 0, depth = 0;
    int width = 0, height = 0;
    bool color_texture = false;
  };
  struct Window {
    GLuint fbo = 0, color = 0, depth = 0;  // the stand-in (0: the window is not scaled)
    int width = 0, height = 0;             // the stand-in's
    ImageSet copy;                         // window-sized: for reads, and a multisampled window's present
    ImageSet resolve;                      // a multisampled stand-in resolved, at its size
    GLenum color_format = GL_RGBA8;
    int samples = 0;
    DepthStencil depth_stencil;
    bool has_depth = false, checked = false;
    // Without blits: the colour is a texture; depth in what the driver has, and stencil in an
    // image of its own where it has no packed depth-stencil.
    bool color_texture = false;
    GLenum depth_format = GL_DEPTH24_STENCIL8;
    GLuint stencil = 0;
    bool separate_stencil = false;
  };
  void check_window();
  void ensure_image_set(ImageSet& set, int width, int height);
  void delete_image_set(ImageSet& set);
  // The stand-in, or its single-sampled resolve (with depth and stencil if asked) when the
  // window is multisampled: what can be blitted at another size.
  GLuint single_sampled_window(bool depth);
  double wanted_window_scale() const { return window_scale_for(config_); }
  double window_scale_for(const Levels& config) const;
  void update_window();
  void release_window();
  void bind_window_copy();
  void unbind_window_copy();
  // The window in a context without blits (window_without_blits.cpp).
  void check_window_without_blits();
  void update_window_without_blits(int width, int height);
  void release_window_without_blits();
  void present_without_blits();
  void bind_window_copy_without_blits();
  // Stand-in images at width x height, the colour a linear-filtered texture.
  void make_drawable_images(GLuint fbo, GLuint* color, GLuint* depth, GLuint* stencil, int width, int height,
                            bool fresh);
  // The app-sized copy a read of the scaled app framebuffer bound for reading goes through:
  // made (or reused), the rectangle blitted into it, bound for reading; false where there is
  // nothing to copy (not scaled, multisampled, an image the scaler does not know).
  bool bind_read_copy(GLint x, GLint y, GLsizei w, GLsizei h, bool depth_stencil);
  void agl_bind_read_framebuffer(GLuint app);
  struct SavedBoxes {
    GLbitfield mask = 0;
    bool window_scaled = false;  // at the push
    std::array<GLint, 4> viewport{}, scissor{};
    std::vector<std::array<GLfloat, 4>> viewports;
    std::vector<std::array<GLint, 4>> scissors;
  };
  // Once the app sets a box by index, every index's (GL_MAX_VIEWPORTS), index 0's mirrored in
  // viewport_ and scissor_; empty before (viewport_arrays.cpp).
  std::vector<std::array<GLfloat, 4>> viewports_;
  std::vector<std::array<GLint, 4>> scissors_;
  bool start_indexed_boxes();
  static std::array<GLfloat, 4> float_box(const std::array<GLint, 4>& box) {
    return {static_cast<GLfloat>(box[0]), static_cast<GLfloat>(box[1]), static_cast<GLfloat>(box[2]),
            static_cast<GLfloat>(box[3])};
  }
  void apply_indexed_boxes(double sx, double sy);
  std::vector<SavedBoxes> attrib_stack_;  // as deep as GL's (GL_ATTRIB_STACK_DEPTH)
  GLuint attrib_fbo_ = 0;                 // attachment-less: takes a pushed GL_COLOR_ATTACHMENT0
  // GL_BACK, or GL_FRONT for a single-buffered window, for the stand-in's GL_COLOR_ATTACHMENT0.
  static GLenum window_name(GLenum attachment_buffer, bool double_buffered);
  std::set<GLuint> viewed_;  // textures made immutable for glTextureView: never scaled
  struct ReadCopy {
    GLuint fbo = 0, image = 0;
    GLenum format = 0;
    bool depth = false;
    int width = 0, height = 0;
  };
  ReadCopy read_copy_;
  double wanted_scale(GLuint name, const Framebuffer& f) const { return scale_for(name, f, config_); }
  double scale_for(GLuint name, const Framebuffer& f, const Levels& config) const;
  bool window_sized(const Framebuffer& f) const;
  bool named_by_manifest(GLuint texture) const;
  void learn_attachments(Framebuffer& f, GLenum target = GL_DRAW_FRAMEBUFFER);
  void ensure_scale(GLuint name, Framebuffer& f, bool carry = true);
  void rescale(GLuint name, Image& image, double scale, bool carry);
  // One level of a texture, with no data, at a size: every face of a cube map, every layer of
  // an array. The texture is bound to its kind.
  static void specify_level(const Image& image, GLint level, GLsizei width, GLsizei height);
  // `object`, a renderbuffer or texture name of `image`'s kind, given level `level` (a
  // renderbuffer: its storage) of `image`'s format and samples at a size; bound after.
  static void allocate_like(const Image& image, GLuint object, GLsizei width, GLsizei height, int level);
  // `object`'s level 0 (layer `layer` of a layered kind) attached to `fbo`, bound to `target`, at
  // the point of `image`'s format.
  static void attach_like(const Image& image, GLenum target, GLuint fbo, GLuint object, GLint layer);
  bool cleared_before_drawn(const Framebuffer& f) const;
  // Blits of each kind a later switch will make, made once on tiny images beforehand
  // (blit_warmup.cpp): those that rescale `f`'s images, and the stand-in's present.
  void warm_rescales(GLuint name, const Framebuffer& f);
  void warm_present();
  void warm_blit(const Image& image, bool pot_width, bool pot_height);
  std::set<std::array<GLint, 7>> warmed_;
  std::set<std::array<int, 2>> warmed_present_;
  void apply_viewport();
  // Keeps the app's box and gives the driver it scaled to the bound draw framebuffer.
  void set_box(std::array<GLint, 4>& box, void(APIENTRYP set)(GLint, GLint, GLsizei, GLsizei), GLint x, GLint y,
               GLsizei w, GLsizei h);
  void scale_of(GLuint fbo, double* sx, double* sy) const;

  Levels config_;
  std::unordered_map<GLuint, Image> textures_, renderbuffers_;
  std::unordered_map<GLuint, Framebuffer> framebuffers_;
  GLuint draw_fbo_ = 0, read_fbo_ = 0;  // the app's names (0: the window)
  Window window_;
  int window_width_ = 0, window_height_ = 0;
  std::array<GLint, 4> viewport_{}, scissor_{};
  bool any_scaled_ = false;
  GlCaps caps_;
  std::unique_ptr<DrawCopy> draw_copy_;  // without blits
  bool window_unscalable_ = false;       // the driver refused the stand-in: said once, not tried again
  uint64_t frame_ = 1;
  uint64_t attachment_changes_ = 0;
  GLint texture_units_ = -1;  // GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, once asked
};

}  // namespace glbudget

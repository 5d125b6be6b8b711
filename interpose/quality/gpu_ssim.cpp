#include "gpu_ssim.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <stdexcept>

#include "glbudget/quality/ssim.hpp"
#include "gpu_ssim_gl.hpp"
#include "gpu_ssim_shaders.hpp"
#include "gpu_ssim_state.hpp"

namespace glbudget {

using namespace gpu_ssim_detail;

namespace {

// EXT_texture_sRGB_decode, not in glcorearb.h.
constexpr GLenum kTextureSrgbDecode = 0x8A48, kDecode = 0x8A49;

bool is_srgb_format(GLint format) {
  switch (format) {
    case GL_SRGB:
    case GL_SRGB8:
    case GL_SRGB_ALPHA:
    case GL_SRGB8_ALPHA8:
    case GL_COMPRESSED_SRGB:
    case GL_COMPRESSED_SRGB_ALPHA:
    case GL_COMPRESSED_SRGB_ALPHA_BPTC_UNORM:
    case GL_COMPRESSED_SRGB8_ETC2:
    case GL_COMPRESSED_SRGB8_PUNCHTHROUGH_ALPHA1_ETC2:
    case GL_COMPRESSED_SRGB8_ALPHA8_ETC2_EAC:
      return true;
    default:
      // S3TC sRGB (EXT_texture_sRGB) and ASTC sRGB (KHR_texture_compression_astc_ldr).
      return (format >= 0x8C4C && format <= 0x8C4F) || (format >= 0x93D0 && format <= 0x93DD);
  }
}

// SSIM's map for a width x height image at a scale: docs/ssim.md's crop, in tiles.
struct Geometry {
  int width = 0, height = 0;  // box-averaged
  int margin_x = 0, margin_y = 0;
  int map_width = 0, map_height = 0;
  int groups_x = 0, groups_y = 0;

  Geometry(int source_width, int source_height, int scale)
      : width((source_width + scale - 1) / scale), height((source_height + scale - 1) / scale) {
    // skimage crops the radius; an axis under the window keeps its middle one or two positions.
    margin_x = std::min(quality::kRadius, (width - 1) / 2);
    margin_y = std::min(quality::kRadius, (height - 1) / 2);
    map_width = width - 2 * margin_x;
    map_height = height - 2 * margin_y;
    groups_x = (map_width + kTile - 1) / kTile;
    groups_y = (map_height + kTile - 1) / kTile;
  }
  int groups() const { return groups_x * groups_y; }
};

struct Program {
  GLuint id = 0;
  // Uniform locations; -1 where the program has none (glUniform* then does nothing).
  GLint size = -1, source_size = -1, scale = -1, srgb = -1, map_origin = -1, map_size = -1, count = -1;
};

}  // namespace

struct GpuSsim::Impl {
  struct Slot {
    std::uint64_t ticket = 0;
    GLuint result_buffer = 0;  // one per slot: mapping a shared one would wait for later tickets
    GLsync fence = nullptr;
    bool flushed = false;
    double count = 0.0;  // map positions averaged
    std::optional<double> value;
  };
  struct Buffer {
    GLuint id = 0;
    GLsizeiptr capacity = 0;
  };

  GlFunctions gl;
  GlCapabilities caps;
  Program downscale, ssim_from_textures, ssim_from_luma, reduce;
  GLuint sampler = 0;
  Buffer luma, partials;
  std::array<Slot, kTicketsKept> slots;
  std::uint64_t next_ticket = 1;

  ~Impl();
  bool build(std::string* why_not);
  bool build_program(Program& program, const std::string& source, std::string* why_not);
  // The buffer bound to `index` of GL_SHADER_STORAGE_BUFFER, with room for `bytes`.
  void bind_storage(Buffer& buffer, GLuint index, GLsizeiptr bytes);
  bool is_srgb_texture(GLuint unit, GLuint texture, int width, int height);
  Slot& slot_of(std::uint64_t ticket);
  void read_result(Slot& slot);
};

GpuSsim::Impl::~Impl() {
  for (Slot& slot : slots) {
    if (slot.fence) gl.DeleteSync(slot.fence);
    if (slot.result_buffer) gl.DeleteBuffers(1, &slot.result_buffer);
  }
  for (Buffer* buffer : {&luma, &partials})
    if (buffer->id) gl.DeleteBuffers(1, &buffer->id);
  if (sampler) gl.DeleteSamplers(1, &sampler);
  for (Program* program : {&downscale, &ssim_from_textures, &ssim_from_luma, &reduce})
    if (program->id) gl.DeleteProgram(program->id);
}

bool GpuSsim::Impl::build_program(Program& program, const std::string& source, std::string* why_not) {
  program.id = build_compute_program(gl, source, why_not);
  if (!program.id) return false;
  const auto location = [&](const char* name) { return gl.GetUniformLocation(program.id, name); };
  program.size = location("size");
  program.source_size = location("source_size");
  program.scale = location("scale");
  program.srgb = location("srgb");
  program.map_origin = location("map_origin");
  program.map_size = location("map_size");
  program.count = location("count");
  return true;
}

bool GpuSsim::Impl::build(std::string* why_not) {
  if (!build_program(downscale, downscale_shader_source(caps), why_not) ||
      !build_program(ssim_from_textures, ssim_shader_source(caps, LumaSource::kTextures), why_not) ||
      !build_program(ssim_from_luma, ssim_shader_source(caps, LumaSource::kBuffer), why_not) ||
      !build_program(reduce, reduce_shader_source(caps), why_not))
    return false;
  // texelFetch of an incomplete texture returns 0, and the app's own texture may be incomplete
  // for sampling (a mipmap filter with one level): our sampler's filter keeps it complete.
  gl.GenSamplers(1, &sampler);
  gl.SamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.SamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  if (caps.srgb_decode_ext) gl.SamplerParameteri(sampler, kTextureSrgbDecode, kDecode);
  return true;
}

void GpuSsim::Impl::bind_storage(Buffer& buffer, GLuint index, GLsizeiptr bytes) {
  if (!buffer.id) gl.GenBuffers(1, &buffer.id);
  gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, index, buffer.id);
  // Grow to fit; shrink when a quarter would do, so that a 4K frame's space is not kept forever.
  if (bytes > buffer.capacity || bytes < buffer.capacity / 4) {
    gl.BufferData(GL_SHADER_STORAGE_BUFFER, bytes, nullptr, GL_DYNAMIC_COPY);
    buffer.capacity = bytes;
  }
}

bool GpuSsim::Impl::is_srgb_texture(GLuint unit, GLuint texture, int width, int height) {
  gl.ActiveTexture(GL_TEXTURE0 + unit);
  gl.BindTexture(GL_TEXTURE_2D, texture);
  GLint texture_width = 0, texture_height = 0, format = 0;
  gl.GetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &texture_width);
  gl.GetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &texture_height);
  gl.GetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
  if (texture_width < width || texture_height < height)
    throw std::invalid_argument("GpuSsim: texture " + std::to_string(texture) + " is " + std::to_string(texture_width) +
                                "x" + std::to_string(texture_height) + ", smaller than the " + std::to_string(width) +
                                "x" + std::to_string(height) + " compared");
  gl.BindSampler(unit, sampler);
  return is_srgb_format(format);
}

GpuSsim::Impl::Slot& GpuSsim::Impl::slot_of(std::uint64_t ticket) {
  Slot& slot = slots[ticket % kTicketsKept];
  if (ticket == 0 || slot.ticket != ticket)
    throw std::out_of_range("GpuSsim: ticket " + std::to_string(ticket) + " is not one of the last " +
                            std::to_string(kTicketsKept) + " submitted");
  return slot;
}

void GpuSsim::Impl::read_result(Slot& slot) {
  GLint bound = 0;
  gl.GetIntegerv(GL_COPY_READ_BUFFER_BINDING, &bound);
  gl.BindBuffer(GL_COPY_READ_BUFFER, slot.result_buffer);
  const void* mapped = gl.MapBufferRange(GL_COPY_READ_BUFFER, 0, sizeof(float), GL_MAP_READ_BIT);
  float sum = 0.0f;
  if (mapped) {
    std::memcpy(&sum, mapped, sizeof sum);
    gl.UnmapBuffer(GL_COPY_READ_BUFFER);
  }
  gl.BindBuffer(GL_COPY_READ_BUFFER, static_cast<GLuint>(bound));
  if (!mapped) throw std::runtime_error("GpuSsim: cannot map the result buffer");
  gl.DeleteSync(slot.fence);
  slot.fence = nullptr;
  // The shaders sum 1 - SSIM: for near-identical frames a small sum, kept to float's relative
  // precision, where a sum of SSIM near 1 would lose digits to the map's size.
  slot.value = 1.0 - static_cast<double>(sum) / slot.count;
}

GpuSsim::GpuSsim(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

GpuSsim::~GpuSsim() = default;

std::unique_ptr<GpuSsim> GpuSsim::create(GlProcLoader load, std::string* why_not) {
  if (!load) {
    if (why_not) *why_not = "no GL loader";
    return nullptr;
  }
  auto impl = std::make_unique<Impl>();
  std::string missing;
  const bool complete = load_gl_functions(load, impl->gl, &missing);
  if (!impl->gl.GetString || !impl->gl.GetIntegerv || !impl->gl.GetStringi) {
    if (why_not) *why_not = "the loader has no " + missing;
    return nullptr;
  }
  if (!query_capabilities(impl->gl, impl->caps, why_not)) return nullptr;
  if (!complete) {
    if (why_not) *why_not = "the loader has no " + missing;
    return nullptr;
  }
  if (!impl->build(why_not)) return nullptr;  // ~Impl releases what was built
  return std::unique_ptr<GpuSsim>(new GpuSsim(std::move(impl)));
}

std::uint64_t GpuSsim::submit(unsigned texture_a, unsigned texture_b, int width, int height, int scale) {
  if (scale != 1 && scale != 2 && scale != 4)
    throw std::invalid_argument("GpuSsim: the scale must be 1, 2 or 4, not " + std::to_string(scale));
  if (width <= 0 || height <= 0) throw std::invalid_argument("GpuSsim: SSIM of an empty image");
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  for (const unsigned texture : {texture_a, texture_b})
    if (!gl.IsTexture(texture))
      throw std::invalid_argument("GpuSsim: " + std::to_string(texture) + " is not a texture");
  const Geometry g(width, height, scale);

  const SavedGlState saved(gl);
  const bool srgb_a = s.is_srgb_texture(kUnitA, texture_a, width, height);
  const bool srgb_b = s.is_srgb_texture(kUnitB, texture_b, width, height);
  // Whatever wrote the textures (image stores included) and our last submit's reads of the
  // buffers we are about to overwrite come first.
  gl.MemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);

  const Program* ssim = &s.ssim_from_textures;
  if (scale > 1) {
    s.bind_storage(s.luma, kLumaBinding, 2 * static_cast<GLsizeiptr>(g.width) * g.height * sizeof(float));
    gl.UseProgram(s.downscale.id);
    gl.Uniform1i(s.downscale.scale, scale);
    gl.Uniform2i(s.downscale.source_size, width, height);
    gl.Uniform2i(s.downscale.size, g.width, g.height);
    gl.Uniform2i(s.downscale.srgb, srgb_a, srgb_b);
    gl.DispatchCompute(static_cast<GLuint>((g.width + kGroupWidth - 1) / kGroupWidth),
                       static_cast<GLuint>((g.height + kGroupHeight - 1) / kGroupHeight), 1);
    gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    ssim = &s.ssim_from_luma;
  }
  s.bind_storage(s.partials, kPartialsBinding, static_cast<GLsizeiptr>(g.groups()) * sizeof(float));
  gl.UseProgram(ssim->id);
  gl.Uniform2i(ssim->size, g.width, g.height);
  gl.Uniform2i(ssim->srgb, srgb_a, srgb_b);
  gl.Uniform2i(ssim->map_origin, g.margin_x, g.margin_y);
  gl.Uniform2i(ssim->map_size, g.map_width, g.map_height);
  gl.DispatchCompute(static_cast<GLuint>(g.groups_x), static_cast<GLuint>(g.groups_y), 1);
  gl.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

  const std::uint64_t ticket = s.next_ticket++;
  Impl::Slot& slot = s.slots[ticket % kTicketsKept];
  if (slot.fence) gl.DeleteSync(slot.fence);  // a ticket nobody read: forgotten
  if (!slot.result_buffer) {
    gl.GenBuffers(1, &slot.result_buffer);
    gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, slot.result_buffer);
    gl.BufferData(GL_SHADER_STORAGE_BUFFER, sizeof(float), nullptr, GL_STREAM_READ);
  }
  gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, kResultBinding, slot.result_buffer);
  gl.UseProgram(s.reduce.id);
  gl.Uniform1i(s.reduce.count, g.groups());
  gl.DispatchCompute(1, 1, 1);
  // The result is read by mapping its buffer.
  gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  slot.fence = gl.FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  slot.ticket = ticket;
  slot.flushed = false;
  slot.count = static_cast<double>(g.map_width) * g.map_height;
  slot.value.reset();
  return ticket;
}

std::optional<double> GpuSsim::poll(std::uint64_t ticket) {
  Impl::Slot& slot = impl_->slot_of(ticket);
  if (slot.value) return slot.value;
  // Flushing once makes sure the fence will signal; it does not wait.
  const GLenum status = impl_->gl.ClientWaitSync(slot.fence, slot.flushed ? 0 : GL_SYNC_FLUSH_COMMANDS_BIT, 0);
  slot.flushed = true;
  if (status == GL_TIMEOUT_EXPIRED) return std::nullopt;
  if (status == GL_WAIT_FAILED) throw std::runtime_error("GpuSsim: glClientWaitSync failed");
  impl_->read_result(slot);
  return slot.value;
}

double GpuSsim::wait(std::uint64_t ticket) {
  Impl::Slot& slot = impl_->slot_of(ticket);
  while (!slot.value) {
    constexpr GLuint64 kSecond = 1000000000;
    const GLenum status = impl_->gl.ClientWaitSync(slot.fence, GL_SYNC_FLUSH_COMMANDS_BIT, kSecond);
    if (status == GL_WAIT_FAILED) throw std::runtime_error("GpuSsim: glClientWaitSync failed");
    if (status != GL_TIMEOUT_EXPIRED) impl_->read_result(slot);
  }
  return *slot.value;
}

}  // namespace glbudget

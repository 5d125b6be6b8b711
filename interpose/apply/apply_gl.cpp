#include "apply_gl.hpp"

#include "hook_table.hpp"

namespace glbudget {

namespace {
template <typename T>
void load(T& fn, const char* name) {
  if (!fn) fn = reinterpret_cast<T>(resolve_gl(name));
}

ApplyGl load_all() {
  ApplyGl g;
  load(g.CreateShader, "glCreateShader");
  load(g.ShaderSource, "glShaderSource");
  load(g.CompileShader, "glCompileShader");
  load(g.GetShaderiv, "glGetShaderiv");
  load(g.GetShaderInfoLog, "glGetShaderInfoLog");
  load(g.DeleteShader, "glDeleteShader");
  load(g.CreateProgram, "glCreateProgram");
  load(g.AttachShader, "glAttachShader");
  load(g.DetachShader, "glDetachShader");
  load(g.LinkProgram, "glLinkProgram");
  load(g.GetProgramiv, "glGetProgramiv");
  load(g.GetProgramInfoLog, "glGetProgramInfoLog");
  load(g.DeleteProgram, "glDeleteProgram");
  load(g.UseProgram, "glUseProgram");
  load(g.ProgramParameteri, "glProgramParameteri");
  load(g.GetActiveAttrib, "glGetActiveAttrib");
  load(g.GetAttribLocation, "glGetAttribLocation");
  load(g.BindAttribLocation, "glBindAttribLocation");
  load(g.BindFragDataLocationIndexed, "glBindFragDataLocationIndexed");
  load(g.GetFragDataLocation, "glGetFragDataLocation");
  load(g.GetFragDataIndex, "glGetFragDataIndex");
  load(g.GetProgramInterfaceiv, "glGetProgramInterfaceiv");
  load(g.GetProgramResourceName, "glGetProgramResourceName");
  load(g.GetProgramResourceIndex, "glGetProgramResourceIndex");
  load(g.GetProgramResourceiv, "glGetProgramResourceiv");
  load(g.TransformFeedbackVaryings, "glTransformFeedbackVaryings");
  load(g.GetTransformFeedbackVarying, "glGetTransformFeedbackVarying");
  load(g.GetActiveUniform, "glGetActiveUniform");
  load(g.GetUniformLocation, "glGetUniformLocation");
  load(g.GetUniformfv, "glGetUniformfv");
  load(g.GetUniformiv, "glGetUniformiv");
  load(g.GetUniformuiv, "glGetUniformuiv");
  load(g.GetUniformdv, "glGetUniformdv");
  load(g.ProgramUniform1fv, "glProgramUniform1fv");
  load(g.ProgramUniform2fv, "glProgramUniform2fv");
  load(g.ProgramUniform3fv, "glProgramUniform3fv");
  load(g.ProgramUniform4fv, "glProgramUniform4fv");
  load(g.ProgramUniform1iv, "glProgramUniform1iv");
  load(g.ProgramUniform2iv, "glProgramUniform2iv");
  load(g.ProgramUniform3iv, "glProgramUniform3iv");
  load(g.ProgramUniform4iv, "glProgramUniform4iv");
  load(g.ProgramUniform1uiv, "glProgramUniform1uiv");
  load(g.ProgramUniform2uiv, "glProgramUniform2uiv");
  load(g.ProgramUniform3uiv, "glProgramUniform3uiv");
  load(g.ProgramUniform4uiv, "glProgramUniform4uiv");
  load(g.ProgramUniform1dv, "glProgramUniform1dv");
  load(g.ProgramUniform2dv, "glProgramUniform2dv");
  load(g.ProgramUniform3dv, "glProgramUniform3dv");
  load(g.ProgramUniform4dv, "glProgramUniform4dv");
  load(g.ProgramUniformMatrix2fv, "glProgramUniformMatrix2fv");
  load(g.ProgramUniformMatrix3fv, "glProgramUniformMatrix3fv");
  load(g.ProgramUniformMatrix4fv, "glProgramUniformMatrix4fv");
  load(g.ProgramUniformMatrix2x3fv, "glProgramUniformMatrix2x3fv");
  load(g.ProgramUniformMatrix3x2fv, "glProgramUniformMatrix3x2fv");
  load(g.ProgramUniformMatrix2x4fv, "glProgramUniformMatrix2x4fv");
  load(g.ProgramUniformMatrix4x2fv, "glProgramUniformMatrix4x2fv");
  load(g.ProgramUniformMatrix3x4fv, "glProgramUniformMatrix3x4fv");
  load(g.ProgramUniformMatrix4x3fv, "glProgramUniformMatrix4x3fv");
  load(g.ProgramUniformMatrix2dv, "glProgramUniformMatrix2dv");
  load(g.ProgramUniformMatrix3dv, "glProgramUniformMatrix3dv");
  load(g.ProgramUniformMatrix4dv, "glProgramUniformMatrix4dv");
  load(g.ProgramUniformMatrix2x3dv, "glProgramUniformMatrix2x3dv");
  load(g.ProgramUniformMatrix3x2dv, "glProgramUniformMatrix3x2dv");
  load(g.ProgramUniformMatrix2x4dv, "glProgramUniformMatrix2x4dv");
  load(g.ProgramUniformMatrix4x2dv, "glProgramUniformMatrix4x2dv");
  load(g.ProgramUniformMatrix3x4dv, "glProgramUniformMatrix3x4dv");
  load(g.ProgramUniformMatrix4x3dv, "glProgramUniformMatrix4x3dv");
  load(g.GetActiveUniformBlockiv, "glGetActiveUniformBlockiv");
  load(g.GetActiveUniformBlockName, "glGetActiveUniformBlockName");
  load(g.GetUniformBlockIndex, "glGetUniformBlockIndex");
  load(g.UniformBlockBinding, "glUniformBlockBinding");
  load(g.ShaderStorageBlockBinding, "glShaderStorageBlockBinding");
  load(g.GetProgramStageiv, "glGetProgramStageiv");
  load(g.GetActiveSubroutineName, "glGetActiveSubroutineName");
  load(g.GetActiveSubroutineUniformName, "glGetActiveSubroutineUniformName");
  load(g.GetActiveSubroutineUniformiv, "glGetActiveSubroutineUniformiv");
  load(g.GetSubroutineIndex, "glGetSubroutineIndex");
  load(g.GetSubroutineUniformLocation, "glGetSubroutineUniformLocation");
  load(g.UniformSubroutinesuiv, "glUniformSubroutinesuiv");
  load(g.GenFramebuffers, "glGenFramebuffers");
  load(g.DeleteFramebuffers, "glDeleteFramebuffers");
  load(g.BindFramebuffer, "glBindFramebuffer");
  load(g.FramebufferTexture2D, "glFramebufferTexture2D");
  load(g.FramebufferTextureLayer, "glFramebufferTextureLayer");
  load(g.FramebufferRenderbuffer, "glFramebufferRenderbuffer");
  load(g.GetFramebufferAttachmentParameteriv, "glGetFramebufferAttachmentParameteriv");
  load(g.BlitFramebuffer, "glBlitFramebuffer");
  load(g.GenRenderbuffers, "glGenRenderbuffers");
  load(g.DeleteRenderbuffers, "glDeleteRenderbuffers");
  load(g.BindRenderbuffer, "glBindRenderbuffer");
  load(g.RenderbufferStorageMultisample, "glRenderbufferStorageMultisample");
  load(g.GenTextures, "glGenTextures");
  load(g.DeleteTextures, "glDeleteTextures");
  load(g.BindTexture, "glBindTexture");
  load(g.ActiveTexture, "glActiveTexture");
  load(g.TexImage2D, "glTexImage2D");
  load(g.TexImage3D, "glTexImage3D");
  load(g.TexImage2DMultisample, "glTexImage2DMultisample");
  load(g.TexParameteri, "glTexParameteri");
  load(g.GetTexParameteriv, "glGetTexParameteriv");
  load(g.Viewport, "glViewport");
  load(g.Scissor, "glScissor");
  load(g.ViewportIndexedf, "glViewportIndexedf");
  load(g.ScissorIndexed, "glScissorIndexed");
  load(g.Enable, "glEnable");
  load(g.Disable, "glDisable");
  load(g.IsEnabled, "glIsEnabled");
  load(g.GetIntegerv, "glGetIntegerv");
  load(g.ReadBuffer, "glReadBuffer");
  load(g.DrawBuffer, "glDrawBuffer");
  return g;
}
}  // namespace

const ApplyGl& agl() {
  static const ApplyGl g = load_all();
  return g;
}

bool apply_gl_has_program_uniforms() {
  const ApplyGl& g = agl();
  return g.ProgramUniform1iv && g.ProgramUniform4fv && g.ProgramUniformMatrix4fv;
}

}  // namespace glbudget

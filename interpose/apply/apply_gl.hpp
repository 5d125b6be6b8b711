// The GL entry points the apply layer calls (variants, render-target scaling), resolved once
// per process. Hooked commands resolve to the driver's function, never to our hook.
#pragma once
#include "gl_types.hpp"

namespace glbudget {

struct ApplyGl {
  // Programs and shaders.
  PFNGLCREATESHADERPROC CreateShader = nullptr;
  PFNGLSHADERSOURCEPROC ShaderSource = nullptr;
  PFNGLCOMPILESHADERPROC CompileShader = nullptr;
  PFNGLGETSHADERIVPROC GetShaderiv = nullptr;
  PFNGLGETSHADERINFOLOGPROC GetShaderInfoLog = nullptr;
  PFNGLDELETESHADERPROC DeleteShader = nullptr;
  PFNGLCREATEPROGRAMPROC CreateProgram = nullptr;
  PFNGLATTACHSHADERPROC AttachShader = nullptr;
  PFNGLDETACHSHADERPROC DetachShader = nullptr;
  PFNGLLINKPROGRAMPROC LinkProgram = nullptr;
  PFNGLGETPROGRAMIVPROC GetProgramiv = nullptr;
  PFNGLGETPROGRAMINFOLOGPROC GetProgramInfoLog = nullptr;
  PFNGLDELETEPROGRAMPROC DeleteProgram = nullptr;
  PFNGLUSEPROGRAMPROC UseProgram = nullptr;
  PFNGLPROGRAMPARAMETERIPROC ProgramParameteri = nullptr;
  PFNGLGETACTIVEATTRIBPROC GetActiveAttrib = nullptr;
  PFNGLGETATTRIBLOCATIONPROC GetAttribLocation = nullptr;
  PFNGLBINDATTRIBLOCATIONPROC BindAttribLocation = nullptr;
  PFNGLBINDFRAGDATALOCATIONINDEXEDPROC BindFragDataLocationIndexed = nullptr;
  PFNGLGETFRAGDATALOCATIONPROC GetFragDataLocation = nullptr;
  PFNGLGETFRAGDATAINDEXPROC GetFragDataIndex = nullptr;
  PFNGLGETPROGRAMINTERFACEIVPROC GetProgramInterfaceiv = nullptr;
  PFNGLGETPROGRAMRESOURCENAMEPROC GetProgramResourceName = nullptr;
  PFNGLGETPROGRAMRESOURCEINDEXPROC GetProgramResourceIndex = nullptr;
  PFNGLGETPROGRAMRESOURCEIVPROC GetProgramResourceiv = nullptr;
  PFNGLTRANSFORMFEEDBACKVARYINGSPROC TransformFeedbackVaryings = nullptr;
  PFNGLGETTRANSFORMFEEDBACKVARYINGPROC GetTransformFeedbackVarying = nullptr;
  // Uniforms and blocks.
  PFNGLGETACTIVEUNIFORMPROC GetActiveUniform = nullptr;
  PFNGLGETUNIFORMLOCATIONPROC GetUniformLocation = nullptr;
  PFNGLGETUNIFORMFVPROC GetUniformfv = nullptr;
  PFNGLGETUNIFORMIVPROC GetUniformiv = nullptr;
  PFNGLGETUNIFORMUIVPROC GetUniformuiv = nullptr;
  PFNGLGETUNIFORMDVPROC GetUniformdv = nullptr;
  PFNGLPROGRAMUNIFORM1FVPROC ProgramUniform1fv = nullptr;
  PFNGLPROGRAMUNIFORM2FVPROC ProgramUniform2fv = nullptr;
  PFNGLPROGRAMUNIFORM3FVPROC ProgramUniform3fv = nullptr;
  PFNGLPROGRAMUNIFORM4FVPROC ProgramUniform4fv = nullptr;
  PFNGLPROGRAMUNIFORM1IVPROC ProgramUniform1iv = nullptr;
  PFNGLPROGRAMUNIFORM2IVPROC ProgramUniform2iv = nullptr;
  PFNGLPROGRAMUNIFORM3IVPROC ProgramUniform3iv = nullptr;
  PFNGLPROGRAMUNIFORM4IVPROC ProgramUniform4iv = nullptr;
  PFNGLPROGRAMUNIFORM1UIVPROC ProgramUniform1uiv = nullptr;
  PFNGLPROGRAMUNIFORM2UIVPROC ProgramUniform2uiv = nullptr;
  PFNGLPROGRAMUNIFORM3UIVPROC ProgramUniform3uiv = nullptr;
  PFNGLPROGRAMUNIFORM4UIVPROC ProgramUniform4uiv = nullptr;
  PFNGLPROGRAMUNIFORM1DVPROC ProgramUniform1dv = nullptr;
  PFNGLPROGRAMUNIFORM2DVPROC ProgramUniform2dv = nullptr;
  PFNGLPROGRAMUNIFORM3DVPROC ProgramUniform3dv = nullptr;
  PFNGLPROGRAMUNIFORM4DVPROC ProgramUniform4dv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX2FVPROC ProgramUniformMatrix2fv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX3FVPROC ProgramUniformMatrix3fv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX4FVPROC ProgramUniformMatrix4fv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX2X3FVPROC ProgramUniformMatrix2x3fv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX3X2FVPROC ProgramUniformMatrix3x2fv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX2X4FVPROC ProgramUniformMatrix2x4fv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX4X2FVPROC ProgramUniformMatrix4x2fv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX3X4FVPROC ProgramUniformMatrix3x4fv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX4X3FVPROC ProgramUniformMatrix4x3fv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX2DVPROC ProgramUniformMatrix2dv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX3DVPROC ProgramUniformMatrix3dv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX4DVPROC ProgramUniformMatrix4dv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX2X3DVPROC ProgramUniformMatrix2x3dv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX3X2DVPROC ProgramUniformMatrix3x2dv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX2X4DVPROC ProgramUniformMatrix2x4dv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX4X2DVPROC ProgramUniformMatrix4x2dv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX3X4DVPROC ProgramUniformMatrix3x4dv = nullptr;
  PFNGLPROGRAMUNIFORMMATRIX4X3DVPROC ProgramUniformMatrix4x3dv = nullptr;
  PFNGLGETACTIVEUNIFORMBLOCKIVPROC GetActiveUniformBlockiv = nullptr;
  PFNGLGETACTIVEUNIFORMBLOCKNAMEPROC GetActiveUniformBlockName = nullptr;
  PFNGLGETUNIFORMBLOCKINDEXPROC GetUniformBlockIndex = nullptr;
  PFNGLUNIFORMBLOCKBINDINGPROC UniformBlockBinding = nullptr;
  PFNGLSHADERSTORAGEBLOCKBINDINGPROC ShaderStorageBlockBinding = nullptr;
  // Subroutine uniforms (GL 4.0).
  PFNGLGETPROGRAMSTAGEIVPROC GetProgramStageiv = nullptr;
  PFNGLGETACTIVESUBROUTINENAMEPROC GetActiveSubroutineName = nullptr;
  PFNGLGETACTIVESUBROUTINEUNIFORMNAMEPROC GetActiveSubroutineUniformName = nullptr;
  PFNGLGETACTIVESUBROUTINEUNIFORMIVPROC GetActiveSubroutineUniformiv = nullptr;
  PFNGLGETSUBROUTINEINDEXPROC GetSubroutineIndex = nullptr;
  PFNGLGETSUBROUTINEUNIFORMLOCATIONPROC GetSubroutineUniformLocation = nullptr;
  PFNGLUNIFORMSUBROUTINESUIVPROC UniformSubroutinesuiv = nullptr;
  // Render targets.
  PFNGLGENFRAMEBUFFERSPROC GenFramebuffers = nullptr;
  PFNGLDELETEFRAMEBUFFERSPROC DeleteFramebuffers = nullptr;
  PFNGLBINDFRAMEBUFFERPROC BindFramebuffer = nullptr;
  PFNGLFRAMEBUFFERTEXTURE2DPROC FramebufferTexture2D = nullptr;
  PFNGLFRAMEBUFFERTEXTURELAYERPROC FramebufferTextureLayer = nullptr;  // GL 3.0, ES 3.0
  PFNGLFRAMEBUFFERRENDERBUFFERPROC FramebufferRenderbuffer = nullptr;
  PFNGLGETFRAMEBUFFERATTACHMENTPARAMETERIVPROC GetFramebufferAttachmentParameteriv = nullptr;
  PFNGLBLITFRAMEBUFFERPROC BlitFramebuffer = nullptr;
  PFNGLGENRENDERBUFFERSPROC GenRenderbuffers = nullptr;
  PFNGLDELETERENDERBUFFERSPROC DeleteRenderbuffers = nullptr;
  PFNGLBINDRENDERBUFFERPROC BindRenderbuffer = nullptr;
  PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC RenderbufferStorageMultisample = nullptr;
  void(APIENTRYP GenTextures)(GLsizei, GLuint*) = nullptr;
  void(APIENTRYP DeleteTextures)(GLsizei, const GLuint*) = nullptr;
  void(APIENTRYP BindTexture)(GLenum, GLuint) = nullptr;
  void(APIENTRYP ActiveTexture)(GLenum) = nullptr;
  void(APIENTRYP TexImage2D)(GLenum, GLint, GLint, GLsizei, GLsizei, GLint, GLenum, GLenum, const void*) = nullptr;
  PFNGLTEXIMAGE3DPROC TexImage3D = nullptr;                        // GL 1.2, ES 3.0
  PFNGLTEXIMAGE2DMULTISAMPLEPROC TexImage2DMultisample = nullptr;  // GL 3.2, not ES
  void(APIENTRYP TexParameteri)(GLenum, GLenum, GLint) = nullptr;
  void(APIENTRYP GetTexParameteriv)(GLenum, GLenum, GLint*) = nullptr;
  void(APIENTRYP Viewport)(GLint, GLint, GLsizei, GLsizei) = nullptr;
  void(APIENTRYP Scissor)(GLint, GLint, GLsizei, GLsizei) = nullptr;
  PFNGLVIEWPORTINDEXEDFPROC ViewportIndexedf = nullptr;  // GL 4.1, ARB_viewport_array
  PFNGLSCISSORINDEXEDPROC ScissorIndexed = nullptr;
  void(APIENTRYP Enable)(GLenum) = nullptr;
  void(APIENTRYP Disable)(GLenum) = nullptr;
  GLboolean(APIENTRYP IsEnabled)(GLenum) = nullptr;
  void(APIENTRYP GetIntegerv)(GLenum, GLint*) = nullptr;
  void(APIENTRYP ReadBuffer)(GLenum) = nullptr;
  void(APIENTRYP DrawBuffer)(GLenum) = nullptr;  // not in GLES
};

const ApplyGl& agl();                  // resolves on first use (a context is current)
bool apply_gl_has_program_uniforms();  // glProgramUniform* (GL 4.1, ES 3.1, ARB_separate_shader_objects)

}  // namespace glbudget

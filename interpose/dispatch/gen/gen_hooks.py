#!/usr/bin/env python3
"""Generates glbudget's GL dispatch layer from the Khronos registry (gl.xml).

Like apitrace, the thousands of possible entry points are described by the registry, not
written by hand. We only *wrap* the commands glbudget needs to observe (draws, program and
shader life cycle, queries, display lists); everything else reaches the driver untouched
because we neither export nor return a wrapper for it.

Outputs (into OUTDIR):
  hooks_generated.hpp    hook ids, typed function-pointer aliases, handler declarations
  hooks_generated.cpp  exported wrappers, name table, build-time hash table for lookups
  exports.map          linker version script: export the wrappers and nothing else
"""
import re
import sys
import xml.etree.ElementTree as ET

# Every draw-like command: its wrapper counts batches, then calls the driver (unless the
# configuration skips the pass).
DRAW_RE = re.compile(r'^gl(Multi)?Draw(Arrays|Elements|RangeElements|TransformFeedback|MeshTasks)')

# Uniform setters: with a variant program in play their values also reach each variant, at the
# variant's location (apply/variants.hpp). glUniform* goes through glProgramUniform*.
UNIFORM_RE = re.compile(r'^gl(Program)?Uniform(Matrix[234](x[234])?|[1234])(fv|iv|uiv|dv|f|i|ui|d|i64v|ui64v|i64|ui64)(ARB|EXT|NV)?$')

# Commands with hand-written handlers in interpose/ (name -> handler base name). Aliases
# from the registry (glBeginQueryARB -> glBeginQuery) share their base command's handler.
CUSTOM = [
    'glUseProgram', 'glUseProgramObjectARB', 'glBindProgramPipeline', 'glUseProgramStages',
    'glShaderSource', 'glAttachShader', 'glDetachShader', 'glLinkProgram',
    'glCreateShaderProgramv', 'glDeleteProgram', 'glDeleteShader', 'glCreateShader',
    'glBeginQuery', 'glEndQuery', 'glBeginQueryIndexed', 'glEndQueryIndexed',
    'glGetQueryiv', 'glGetQueryIndexediv',
    'glCompileShader', 'glGetShaderSource', 'glGetShaderiv', 'glGetProgramBinary',
    'glBegin', 'glEnd', 'glNewList', 'glEndList', 'glCallList', 'glCallLists',
    # apply/: variants and render-target scaling
    'glUniformBlockBinding', 'glShaderStorageBlockBinding',
    'glUniformSubroutinesuiv', 'glGetUniformSubroutineuiv',  # apply/subroutines.cpp
    'glGetIntegerv', 'glGetInteger64v', 'glGetFloatv', 'glGetDoublev', 'glGetBooleanv',
    'glBindFramebuffer', 'glViewport', 'glScissor', 'glTexImage2D', 'glRenderbufferStorage',
    'glRenderbufferStorageMultisample', 'glFramebufferTexture2D', 'glFramebufferTexture',
    'glFramebufferRenderbuffer', 'glBlitFramebuffer', 'glGetTexLevelParameteriv',
    'glGetTexLevelParameterfv', 'glGetRenderbufferParameteriv', 'glDeleteTextures',
    'glDeleteFramebuffers', 'glDeleteRenderbuffers',
    'glTexStorage2D', 'glGetTexParameteriv', 'glTexParameteri', 'glTexParameteriv',
    'glTextureStorage2D', 'glGetTextureParameteriv', 'glTextureParameteri', 'glTextureParameteriv',
    'glGetTextureLevelParameteriv', 'glGetTextureLevelParameterfv',
    'glTexImage3D', 'glTexStorage3D', 'glTextureStorage3D', 'glFramebufferTextureLayer',  # arrays, cube maps
    'glTexImage2DMultisample', 'glTexStorage2DMultisample', 'glTextureStorage2DMultisample',
    'glNamedFramebufferTexture', 'glNamedFramebufferTextureLayer', 'glNamedFramebufferRenderbuffer',
    'glGenerateMipmap', 'glGenerateTextureMipmap',  # apply/probes.cpp: shadows' levels too
    # apply/: the default framebuffer's stand-in
    'glReadPixels', 'glCopyTexImage2D', 'glCopyTexSubImage2D', 'glDrawBuffer', 'glDrawBuffers', 'glReadBuffer',
    'glInvalidateFramebuffer', 'glInvalidateSubFramebuffer', 'glDiscardFramebufferEXT',
    'glGetFramebufferAttachmentParameteriv', 'glBlitNamedFramebuffer', 'glNamedFramebufferDrawBuffer',
    'glNamedFramebufferDrawBuffers', 'glNamedFramebufferReadBuffer', 'glClearNamedFramebufferiv',
    'glClearNamedFramebufferuiv', 'glClearNamedFramebufferfv', 'glClearNamedFramebufferfi',
    'glClear', 'glClearBufferfv', 'glClearBufferiv', 'glClearBufferuiv', 'glClearBufferfi',
    'glTextureView',  # apply/: a view needs the driver's immutable storage
    # apply/viewport_arrays.cpp: viewport arrays scaled and answered as glViewport is
    'glViewportIndexedf', 'glViewportIndexedfv', 'glViewportArrayv', 'glScissorIndexed', 'glScissorIndexedv',
    'glScissorArrayv', 'glGetFloati_v', 'glGetIntegeri_v', 'glGetDoublei_v', 'glGetInteger64i_v',
    'glPushAttrib', 'glPopAttrib',  # apply/: the app's viewport and the window's read buffer across them
    'glBindAttribLocation', 'glBindFragDataLocation', 'glBindFragDataLocationIndexed',
    'glActiveShaderProgram', 'glGetProgramPipelineiv',
    'glGetError',  # state/gl_errors.cpp: the app's errors, kept apart from the shim's own
]
ALIASES_OF_CUSTOM = {
    'glUseProgramObjectARB': 'glUseProgram',
    'glBeginQueryARB': 'glBeginQuery', 'glBeginQueryEXT': 'glBeginQuery',
    'glEndQueryARB': 'glEndQuery', 'glEndQueryEXT': 'glEndQuery',
    'glGetQueryivARB': 'glGetQueryiv', 'glGetQueryivEXT': 'glGetQueryiv',
    'glShaderSourceARB': 'glShaderSource', 'glAttachObjectARB': 'glAttachShader',
    'glDetachObjectARB': 'glDetachShader', 'glLinkProgramARB': 'glLinkProgram',
    'glCreateShaderObjectARB': 'glCreateShader',
    'glBindProgramPipelineEXT': 'glBindProgramPipeline',
    'glUseProgramStagesEXT': 'glUseProgramStages',
    'glCompileShaderARB': 'glCompileShader', 'glGetShaderSourceARB': 'glGetShaderSource',
    'glGetProgramBinaryOES': 'glGetProgramBinary',
    'glBindFramebufferEXT': 'glBindFramebuffer', 'glFramebufferTexture2DEXT': 'glFramebufferTexture2D',
    'glFramebufferRenderbufferEXT': 'glFramebufferRenderbuffer', 'glRenderbufferStorageEXT': 'glRenderbufferStorage',
    'glBlitFramebufferEXT': 'glBlitFramebuffer', 'glDeleteFramebuffersEXT': 'glDeleteFramebuffers',
    'glDeleteRenderbuffersEXT': 'glDeleteRenderbuffers', 'glGetRenderbufferParameterivEXT': 'glGetRenderbufferParameteriv',
    'glRenderbufferStorageMultisampleEXT': 'glRenderbufferStorageMultisample',
    'glGetFramebufferAttachmentParameterivEXT': 'glGetFramebufferAttachmentParameteriv',
    'glDrawBuffersARB': 'glDrawBuffers', 'glDrawBuffersEXT': 'glDrawBuffers',
    'glBindAttribLocationARB': 'glBindAttribLocation', 'glBindFragDataLocationEXT': 'glBindFragDataLocation',
    'glTexStorage2DEXT': 'glTexStorage2D', 'glTexStorage3DEXT': 'glTexStorage3D',
    'glFramebufferTextureLayerEXT': 'glFramebufferTextureLayer', 'glFramebufferTextureLayerARB': 'glFramebufferTextureLayer',
    'glGenerateMipmapEXT': 'glGenerateMipmap',
    'glTextureViewOES': 'glTextureView', 'glTextureViewEXT': 'glTextureView',
}

# Window-system entry points: implemented by hand (they carry frame and context logic), but
# they share the generated id space and hash table so one lookup serves GetProcAddress/dlsym.
WINSYS = [
    'glXGetProcAddress', 'glXGetProcAddressARB', 'glXMakeCurrent', 'glXMakeContextCurrent',
    'glXCreateContext', 'glXCreateNewContext', 'glXCreateContextAttribsARB',
    'glXDestroyContext', 'glXSwapBuffers',
    'eglGetProcAddress', 'eglMakeCurrent', 'eglCreateContext', 'eglDestroyContext',
    'eglSwapBuffers', 'eglSwapBuffersWithDamageKHR', 'eglSwapBuffersWithDamageEXT',
    'eglTerminate', 'eglReleaseThread',
]


def text_of(elem):
    return ''.join(elem.itertext()).strip()


class Command:
    def __init__(self, elem):
        proto = elem.find('proto')
        self.name = proto.find('name').text
        self.ret = text_of(proto)[: -len(self.name)].strip()
        self.params = []  # (type, name, ptype)
        for p in elem.findall('param'):
            pname = p.find('name').text
            full = text_of(p)
            ptype_el = p.find('ptype')
            self.params.append((full[: full.rfind(pname)].strip(), pname,
                                ptype_el.text if ptype_el is not None else None))
        alias = elem.find('alias')
        self.alias = alias.get('name') if alias is not None else None

    def decl_params(self):
        return ', '.join(f'{t} {n}' for t, n, _ in self.params) or 'void'

    def arg_names(self):
        return ', '.join(n for _, n, _ in self.params)

    def pfn(self):
        return f'pfn_{self.name}'

    def batches_expr(self):
        if self.name.startswith('glMultiDraw'):
            for t, n, pt in self.params:
                if n in ('drawcount', 'primcount') and t == 'GLsizei':
                    return n
        if self.name == 'glCallLists':
            return 'n'
        return '1'


def main():
    registry, outdir = sys.argv[1], sys.argv[2]
    root = ET.parse(registry).getroot()
    commands = {c.name: c for c in (Command(e) for e in root.find('commands').findall('command'))}

    draws = sorted(n for n in commands if DRAW_RE.match(n)) + ['glCallList', 'glCallLists']
    custom = sorted(set(CUSTOM) | set(ALIASES_OF_CUSTOM))
    missing = [n for n in custom + draws if n not in commands]
    if missing:
        sys.exit(f'gen_hooks: registry lacks {missing}')
    draws = [n for n in draws if n not in ('glCallList', 'glCallLists')] + ['glCallList', 'glCallLists']
    uniforms = sorted(n for n in commands if UNIFORM_RE.match(n))

    def program_form(name):
        # glUniform4fvARB -> glProgramUniform4fv: the program-taking command with the same arguments.
        if name.startswith('glProgram'):
            return name
        for cand in ('glProgram' + name[2:], 'glProgram' + re.sub(r'(ARB|EXT|NV)$', '', name[2:])):
            if cand in commands:
                return cand
        return None
    uniforms = [n for n in uniforms if program_form(n)]
    for n in list(uniforms):
        if program_form(n) not in uniforms:
            uniforms.append(program_form(n))
    gl_hooks = draws + [n for n in custom if n not in draws] + [n for n in uniforms if n not in custom]
    all_hooks = gl_hooks + WINSYS

    def handler_base(name):
        return ALIASES_OF_CUSTOM.get(name, name)

    h = []
    h.append('// Generated by interpose/dispatch/gen/gen_hooks.py from gl.xml. Do not edit.')
    h.append('#pragma once')
    h.append('#include "gl_types.hpp"')
    h.append('namespace glbudget {')
    h.append('enum HookId : int {')
    for i, n in enumerate(all_hooks):
        h.append(f'  kHook_{n} = {i},')
    h.append(f'  kHookCount = {len(all_hooks)},')
    h.append(f'  kFirstWinsysHook = {len(gl_hooks)},')
    h.append('};')
    for n in gl_hooks:
        c = commands[n]
        h.append(f'using {c.pfn()} = {c.ret} (APIENTRYP)({c.decl_params()});')
    h.append('// Hand-written handlers (interpose/*/gl_*.cpp, apply/). Each receives the real entry point.')
    for n in sorted({handler_base(n) for n in custom}):
        c = commands[n]
        args = ', '.join([f'{c.pfn()} real'] + [f'{t} {p}' for t, p, _ in c.params])
        h.append(f'{c.ret} handle_{n}({args});')
    h.append('}  // namespace glbudget')

    cpp = []
    cpp.append('// Generated by interpose/dispatch/gen/gen_hooks.py from gl.xml. Do not edit.')
    cpp.append('#include "hooks_generated.hpp"')
    cpp.append('#include "hook_table.hpp"')
    cpp.append('#include "draw_count.hpp"')
    cpp.append('#include "uniform_fanout.hpp"')
    cpp.append('#include "probes.hpp"')
    cpp.append('using namespace glbudget;')
    for n in gl_hooks:
        c = commands[n]
        ret_void = c.ret == 'void'
        fail = 'return;' if ret_void else f'return {c.ret}{{}};'
        cpp.append(f'GLBUDGET_EXPORT {c.ret} APIENTRY {n}({c.decl_params()}) {{')
        cpp.append(f'  auto real = reinterpret_cast<{c.pfn()}>(real_entry(kHook_{n}));')
        cpp.append(f'  if (!real) {fail}')
        if n in uniforms:
            names = [p[1] for p in c.params]
            if n.startswith('glProgram'):
                rest = ', '.join(names[2:])
                cpp.append(f'  const UniformTargets* t = program_uniform_targets({names[0]}, {names[1]});')
                cpp.append(f'  if (!t) return real({c.arg_names()});')
                cpp.append(f'  for (int i = 0; i < t->count; ++i) real(t->program[i], t->location[i]{", " if rest else ""}{rest});')
            else:
                pf = program_form(n)
                rest = ', '.join(names[1:])
                cpp.append(f'  const UniformTargets* t = bound_uniform_targets({names[0]});')
                cpp.append(f'  auto prog = t ? reinterpret_cast<{commands[pf].pfn()}>(real_entry(kHook_{pf})) : nullptr;')
                cpp.append(f'  if (!prog) return real({c.arg_names()});')
                cpp.append(f'  for (int i = 0; i < t->count; ++i) prog(t->program[i], t->location[i]{", " if rest else ""}{rest});')
        elif n in custom:
            base = commands[handler_base(n)]
            cast = '' if base.name == n else f'reinterpret_cast<{base.pfn()}>'
            call = f'handle_{base.name}({cast}(real){", " if c.params else ""}{c.arg_names()})'
            cpp.append(f'  {"" if ret_void else "return "}{call};')
        else:
            if ret_void:
                # On probe frames (apply/probes.hpp) the draw is issued again for each probe
                # stream, after the app's, and the streams' targets are readied before it.
                cpp.append(f'  const bool drawn = count_draw({c.batches_expr()});')
                cpp.append('  ProbeFrames* probe = t_probe;')
                cpp.append('  if (probe) [[unlikely]] probe->prepare();')
                cpp.append(f'  if (drawn) real({c.arg_names()});')
                cpp.append(f'  if (probe) [[unlikely]] probe_draw([&] {{ real({c.arg_names()}); }});')
            else:
                cpp.append(f'  if (!count_draw({c.batches_expr()})) {fail}')
                cpp.append(f'  return real({c.arg_names()});')
        cpp.append('}')

    # Build-time open-addressing hash table: FNV-1a 64, linear probing, load factor <= 1/4.
    size = 1
    while size < 4 * len(all_hooks):
        size *= 2

    def fnv1a(s):
        x = 0xcbf29ce484222325
        for ch in s.encode():
            x ^= ch
            x = (x * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
        return x
    slots = [-1] * size
    for i, n in enumerate(all_hooks):
        j = fnv1a(n) & (size - 1)
        while slots[j] != -1:
            j = (j + 1) & (size - 1)
        slots[j] = i
    cpp.append('namespace glbudget {')
    cpp.append('const char* const kHookNames[kHookCount] = {')
    cpp.extend(f'  "{n}",' for n in all_hooks)
    cpp.append('};')
    for n in WINSYS:
        cpp.append(f'extern "C" void {n}();  // address only; real prototype in winsys code')
    cpp.append('void* const kHookAddress[kHookCount] = {')
    cpp.extend(f'  reinterpret_cast<void*>(&::{n}),' for n in all_hooks)
    cpp.append('};')
    cpp.append(f'const int kHashSlots = {size};')
    cpp.append(f'const short kHashTable[{size}] = {{{", ".join(map(str, slots))}}};')
    cpp.append('}  // namespace glbudget')

    with open(f'{outdir}/hooks_generated.hpp', 'w') as f:
        f.write('\n'.join(h) + '\n')
    with open(f'{outdir}/hooks_generated.cpp', 'w') as f:
        f.write('\n'.join(cpp) + '\n')
    with open(f'{outdir}/exports.map', 'w') as f:
        f.write('{\n  global:\n')
        for n in all_hooks + ['dlsym', '_exit', '_Exit', 'sigaction', 'signal', 'bsd_signal']:
            f.write(f'    {n};\n')
        f.write('  local: *;\n};\n')


if __name__ == '__main__':
    main()

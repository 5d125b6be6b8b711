// Subroutine uniforms (GL 4.0) under program shadowing. Subroutine indices and subroutine-uniform
// locations belong to a program, as uniform locations do, and GL resets the selections at every
// glUseProgram. While the app's program has variants, the app's glUniformSubroutinesuiv is kept
// per context and stage in the app's terms (ContextState::subroutines) and reaches whichever
// program the driver has bound through that variant's tables (apply/variants.hpp, built with it);
// glbudget re-applies it after each glUseProgram of its own, and glGetUniformSubroutineuiv
// answers it while a variant is bound. Programs without variants: the calls go straight through.
// The handlers (handle_glUniformSubroutinesuiv, handle_glGetUniformSubroutineuiv) are declared
// in hooks_generated.hpp.
#pragma once

namespace glbudget {

struct ContextState;

// After glbudget's own glUseProgram (bind_program): the app's selections, in the terms of the
// program the driver now has bound. A variant bound before the app selected anything gets the
// app program's first compatible subroutine per location.
void reapply_subroutines(ContextState& c);

}  // namespace glbudget

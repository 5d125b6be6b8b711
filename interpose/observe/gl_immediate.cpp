// Compatibility-profile drawing: glBegin/glEnd and display lists.
#include "context_state.hpp"
#include "hooks_generated.hpp"

namespace glbudget {

// Between glBegin and glEnd almost no GL command is legal, ours included: the pass switch
// and the batch are accounted before the real glBegin. Immediate mode is never skipped (the
// vertex calls up to glEnd would then reach the driver outside glBegin/glEnd).
void handle_glBegin(pfn_glBegin real, GLenum mode) {
  (void)count_draw(1);
  real(mode);
}

void handle_glEnd(pfn_glEnd real) { real(); }

// Draws compiled into a list (GL_COMPILE) draw nothing now; they count when the list is called.
void handle_glNewList(pfn_glNewList real, GLuint list, GLenum mode) {
  real(list, mode);
  ContextState* c = current_context();
  if (!c) return;
  c->list_compile_only = mode == GL_COMPILE;
  if (c->list_compile_only) c->counter->set_counting(false);
}

void handle_glEndList(pfn_glEndList real) {
  real();
  ContextState* c = current_context();
  if (!c) return;
  if (c->list_compile_only) c->counter->set_counting(true);
  c->list_compile_only = false;
}

// A called list counts as one batch (its contents are not inspected).
void handle_glCallList(pfn_glCallList real, GLuint list) {
  if (count_draw(1)) real(list);
}

void handle_glCallLists(pfn_glCallLists real, GLsizei n, GLenum type, const void* lists) {
  if (n > 0 && !count_draw(static_cast<uint64_t>(n))) return;
  real(n, type, lists);
}

}  // namespace glbudget

#include "uniform_fanout.hpp"

#include "context_state.hpp"

namespace glbudget {

namespace {
thread_local UniformTargets t_targets;
}

const UniformTargets* bound_uniform_targets(GLint location) {
  const ContextState* c = current_context();
  if (!c) return nullptr;
  const VariantSet* v = c->bound_variants ? c->bound_variants.get() : c->pipeline_uniform_variants.get();
  if (!v) return nullptr;
  uniform_targets(*v, location, &t_targets);
  return &t_targets;
}

const UniformTargets* program_uniform_targets(GLuint program, GLint location) {
  ContextState* c = current_context();
  if (!c || !c->group->has_variants.load(std::memory_order_relaxed)) return nullptr;
  std::shared_ptr<const VariantSet> variants;
  if (c->bound_variants && c->bound_variants->app_program == program) {
    variants = c->bound_variants;
  } else {
    std::lock_guard lock(c->group->mu);
    auto it = c->group->programs.find(program);
    if (it == c->group->programs.end() || !it->second.variants) return nullptr;
    variants = it->second.variants;
  }
  uniform_targets(*variants, location, &t_targets);
  return &t_targets;
}

}  // namespace glbudget

#include "rewrite.hpp"

#include <algorithm>
#include <stdexcept>

namespace glbudget::instrument {

namespace {

using syntax::Range;
using syntax::Statement;
using Kind = Statement::Kind;

struct Tally {
  std::uint64_t operations = 0;
  std::uint64_t texel_accesses = 0;
  bool any() const { return operations || texel_accesses; }
  Tally& operator+=(const Tally& o) {
    operations += o.operations;
    texel_accesses += o.texel_accesses;
    return *this;
  }
};

// Census nodes by text offset; each is claimed by exactly one block.
class NodeIndex {
 public:
  NodeIndex(std::string_view text, const std::vector<CountedNode>& nodes) {
    std::vector<std::size_t> line_starts{0};
    for (std::size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') line_starts.push_back(i + 1);
    for (const CountedNode& n : nodes) {
      if (n.line < 1 || n.line > static_cast<int>(line_starts.size()) || n.column < 1)
        throw std::runtime_error("glslang gave an operation no source position");
      entries_.push_back({line_starts[n.line - 1] + n.column - 1, n.texel_access, false});
    }
    std::stable_sort(entries_.begin(), entries_.end(),
                     [](const Entry& a, const Entry& b) { return a.offset < b.offset; });
  }

  Tally claim(Range range) {
    Tally tally;
    for (auto it = lower(range.begin); it != entries_.end() && it->offset < range.end; ++it) {
      if (it->claimed) throw std::runtime_error("an operation falls in two blocks");
      it->claimed = true;
      ++tally.operations;
      tally.texel_accesses += it->texel;
    }
    return tally;
  }

  // Nodes outside every function (global initialisers) run when main starts.
  Tally claim_outside(const std::vector<syntax::Function>& functions) {
    Tally tally;
    for (Entry& e : entries_) {
      const bool in_function = std::any_of(functions.begin(), functions.end(), [&](const auto& f) {
        return e.offset >= f.whole.begin && e.offset < f.whole.end;
      });
      if (in_function || e.claimed) continue;
      e.claimed = true;
      ++tally.operations;
      tally.texel_accesses += e.texel;
    }
    return tally;
  }

  std::size_t unclaimed() const {
    return std::count_if(entries_.begin(), entries_.end(), [](const Entry& e) { return !e.claimed; });
  }

 private:
  struct Entry {
    std::size_t offset;
    bool texel;
    bool claimed;
  };
  std::vector<Entry>::iterator lower(std::size_t offset) {
    return std::lower_bound(entries_.begin(), entries_.end(), offset,
                            [](const Entry& e, std::size_t o) { return e.offset < o; });
  }
  std::vector<Entry> entries_;
};

std::string increments(const Tally& t, std::string_view separator) {
  std::string s;
  auto add = [&](std::string_view variable, std::uint64_t amount) {
    if (!amount) return;
    s += std::string(variable) + " += " + std::to_string(amount) + "u" + std::string(separator);
  };
  add(kInstructionVariable, t.operations);
  add(kTexelVariable, t.texel_accesses);
  return s;
}

std::vector<const Statement*> pointers(const syntax::StatementList& statements) {
  std::vector<const Statement*> result;
  for (const auto& s : statements) result.push_back(s.get());
  return result;
}

class Planner {
 public:
  Planner(std::string_view text, const std::vector<CountedNode>& nodes) : index_(text, nodes) {}

  BodyPlan run(const syntax::Unit& unit) {
    const syntax::Function* main = nullptr;
    for (const auto& f : unit.functions)
      if (f.name == "main") main = &f;
    if (!main) throw std::runtime_error("the shader has no main()");
    entry_extra_ = index_.claim_outside(unit.functions);
    for (const auto& f : unit.functions) {
      in_main_ = &f == main;
      list(pointers(f.body->children), f.body->whole.begin + 1);
      if (in_main_ && !ends_in_jump(*f.body)) insert(f.body->whole.end - 1, std::string(kFlushFunction) + "(); ");
    }
    if (const std::size_t lost = index_.unclaimed())
      throw std::runtime_error(std::to_string(lost) + " operations lie outside every block");
    return std::move(plan_);
  }

 private:
  static bool ends_in_jump(const Statement& compound) {
    if (compound.children.empty()) return false;
    const Kind k = compound.children.back()->kind;
    return k == Kind::return_ || k == Kind::discard;
  }

  void insert(std::size_t offset, std::string text) { plan_.insertions.push_back({offset, std::move(text)}); }

  // One basic block: a straight-line run of statements, counted where it starts.
  // Its counter is a placeholder insertion made when the run opens, so that it precedes
  // whatever the run's statements insert at the same offset; close() fills it in.
  struct Run {
    std::size_t slot = 0;
    Tally tally;
    bool has_content = false;
  };

  Run open(std::size_t start) {
    insert(start, "");
    return Run{plan_.insertions.size() - 1, {}, false};
  }

  void close(Run& run) {
    if (run.has_content) ++plan_.figures.blocks;
    plan_.insertions[run.slot].text = increments(run.tally, "; ");
    add_static(run.tally);
  }

  void add_static(const Tally& t) {
    plan_.figures.instructions += t.operations;
    plan_.figures.texture_calls += static_cast<int>(t.texel_accesses);
  }

  // A statement list whose first run starts at `start`.
  void list(const std::vector<const Statement*>& statements, std::size_t start) {
    Run run = open(start);
    if (in_main_ && !entry_counted_) {  // global initialisers run as main starts
      run.tally += entry_extra_;
      entry_counted_ = true;
    }
    for (const auto& s : statements) {
      switch (s->kind) {
        case Kind::empty:
          break;
        case Kind::simple:
          run.tally += index_.claim(s->whole);
          run.has_content = true;
          break;
        case Kind::return_:
        case Kind::discard:
        case Kind::break_:
        case Kind::continue_:
          run.tally += index_.claim(s->head);
          run.has_content = true;
          if (s->kind == Kind::discard || (in_main_ && s->kind == Kind::return_))
            insert(s->whole.begin, std::string(kFlushFunction) + "(); ");
          close(run);
          run = open(s->whole.end);
          break;
        case Kind::label:
          close(run);
          run = open(s->whole.end);
          break;
        default:
          run.tally += index_.claim(header(*s));
          run.has_content |= !header(*s).empty();
          close(run);
          control(*s);
          run = open(s->whole.end);
      }
    }
    close(run);
  }

  // The part of a control statement that executes once, in the enclosing block.
  static Range header(const Statement& s) {
    switch (s.kind) {
      case Kind::if_:
      case Kind::switch_:
        return s.head;
      case Kind::for_:
        return s.init;
      default:
        return {};
    }
  }

  void control(const Statement& s) {
    switch (s.kind) {
      case Kind::compound:
        list(pointers(s.children), s.whole.begin + 1);
        break;
      case Kind::switch_:
        list(pointers(s.children), s.whole.end - 1);
        break;  // labels start the runs
      case Kind::if_:
        nested(*s.body);
        if (s.else_body) nested(*s.else_body);
        break;
      case Kind::for_:
        loop_expression(s.head);
        loop_expression(s.step);
        nested(*s.body);
        break;
      case Kind::while_:
      case Kind::do_while:
        loop_expression(s.head);
        nested(*s.body);
        break;
      default:
        break;
    }
  }

  // A loop condition or step: counted each time it is evaluated, with a comma expression.
  void loop_expression(Range r) {
    if (r.empty()) return;
    const Tally t = index_.claim(r);
    ++plan_.figures.blocks;
    add_static(t);
    if (!t.any()) return;
    std::string counted = increments(t, ", ");
    insert(r.begin, "(" + counted);
    insert(r.end, ")");
  }

  // A branch or loop body; an unbraced one gets braces so the counter can precede it.
  void nested(const Statement& body) {
    if (body.kind == Kind::compound) {
      list(pointers(body.children), body.whole.begin + 1);
      return;
    }
    insert(body.whole.begin, "{ ");
    // The closing brace must follow everything the body inserts at its end, and anything
    // inserted there later (by the enclosing list) must follow the brace.
    const std::size_t close_index = plan_.insertions.size();
    insert(body.whole.end, " }");
    list({&body}, body.whole.begin);
    move_to_back(close_index);
  }

  void move_to_back(std::size_t index) {
    Insertion moved = std::move(plan_.insertions[index]);
    plan_.insertions.erase(plan_.insertions.begin() + static_cast<std::ptrdiff_t>(index));
    plan_.insertions.push_back(std::move(moved));
  }

  NodeIndex index_;
  BodyPlan plan_;
  Tally entry_extra_;
  bool entry_counted_ = false;
  bool in_main_ = false;
};

}  // namespace

BodyPlan plan_body(std::string_view text, const syntax::Unit& unit, const std::vector<CountedNode>& nodes) {
  return Planner(text, nodes).run(unit);
}

std::string apply_insertions(std::string_view text, std::vector<Insertion> insertions) {
  std::stable_sort(insertions.begin(), insertions.end(),
                   [](const Insertion& a, const Insertion& b) { return a.offset < b.offset; });
  std::string out;
  out.reserve(text.size() + insertions.size() * 32);
  std::size_t done = 0;
  for (const Insertion& ins : insertions) {
    out.append(text.substr(done, ins.offset - done));
    out += ins.text;
    done = ins.offset;
  }
  out.append(text.substr(done));
  return out;
}

}  // namespace glbudget::instrument

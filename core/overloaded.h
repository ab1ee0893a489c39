// One call object from several lambdas, for std::visit over a std::variant:
//
//   std::visit(overloaded{[](const Sphere& s) { ... }, [](const Disk& d) { ... }, ...}, shape);
//
// Write one lambda per alternative (no `auto` catch-all): a variant that
// gains an alternative then fails to compile at every visit until each one
// handles it.
#pragma once

namespace furnace {

template <class... Fs>
struct overloaded : Fs... {
  using Fs::operator()...;
};
template <class... Fs>
overloaded(Fs...) -> overloaded<Fs...>;

}  // namespace furnace

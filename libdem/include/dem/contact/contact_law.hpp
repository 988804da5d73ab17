// Pluggable contact laws. A law is a plain type that knows its two pieces and nothing else (no
// walls, threads, processes or worlds):
//
//   struct MyLaw {
//     struct Params { ...; void validate(const std::string& where) const; };   // SI
//     struct State  { ... };   // per-contact history; a value-initialised State is a fresh contact
//     static constexpr const char* name = "my-law";
//     static ContactForce force(const Params&, const ContactKinematics&, State&);
//     static ContactStiffness stiffness(const Params&, const ContactKinematics&);
//   };
//
// `make_contact_model<MyLaw>(params)` (dem/core/contact_model.hpp) binds it to its parameters and
// to the engine's loops, for one contact type of a World: the choice of law is made at run time,
// once per contact type, and the loop over the contacts of that type is a template on the concrete
// law (run-time choice, compile-time loop), so a new law costs no engine edit and no virtual call
// per contact. A law may also offer a plain-double force_lanes (lanes.hpp) for the SIMD blocks.
#pragma once

#include <concepts>
#include <string>
#include <type_traits>

#include <dem/contact/kinematics.hpp>

namespace dem {

template <class L>
concept ContactLaw = requires(const typename L::Params& p, const ContactKinematics& k, typename L::State& s) {
  { L::force(p, k, s) } -> std::same_as<ContactForce>;
  { L::stiffness(p, k) } -> std::same_as<ContactStiffness>;
  { p.validate(std::string{}) };
  { L::name } -> std::convertible_to<const char*>;
} && std::is_trivially_destructible_v<typename L::State> && std::is_default_constructible_v<typename L::State>;

}  // namespace dem

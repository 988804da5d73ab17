// The library's instantiation of the Hertz-DMT law's contact loops (the registry's row declares it
// extern), in a file of its own as Hertz-Mindlin's: one contact at a time (the law has no lanes).
#include <dem/contact/hertz_dmt_law.hpp>
#include <dem/core/contact_loops.hpp>

namespace dem {

template std::shared_ptr<const ContactModel> make_contact_model<HertzDmtLaw>(const HertzDmtLaw::Params&,
                                                                            const std::string&);

}  // namespace dem

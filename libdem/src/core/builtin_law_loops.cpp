// The one instantiation of the linear laws' contact loops (contact/linear_law.hpp declares them
// extern): programs that use the laws link these, compiled with the library's flags whatever theirs.
#include <dem/contact/linear_law.hpp>
#include <dem/core/contact_loops.hpp>

namespace dem {

template std::shared_ptr<const ContactModel> make_contact_model<LinearLaw>(const LinearLaw::Params&, const std::string&);
template std::shared_ptr<const ContactModel> make_contact_model<RollingLinearLaw>(const RollingLinearLaw::Params&,
                                                                                 const std::string&);

}  // namespace dem

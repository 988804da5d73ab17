// The one instantiation of the Hertz-Mindlin law's contact loops (core/contact_model.hpp declares
// it extern), in a file of its own: the linear laws' loops stay the same machine code.
#include <dem/contact/hertz_mindlin_law.hpp>
#include <dem/core/contact_loops.hpp>

namespace dem {

template std::shared_ptr<const ContactModel> make_contact_model<HertzMindlinLaw>(const HertzMindlinLaw::Params&,
                                                                                const std::string&);

}  // namespace dem

// The library's one Registry<ContactModel> (contact_model.h), compiled here
// so that the interface builds with the library before any model exists.
#include <perideal/contact/contact_model.h>

namespace perideal
{
  template class Registry<ContactModel>;

  void
  declare_contact_model_entry(ParameterHandler &prm)
  {
    prm.declare_entry("Model", "", dealii::Patterns::Anything(),
                      "The contact model: one of " + Registry<ContactModel>::instance().names(", ") + ".");
  }
} // namespace perideal

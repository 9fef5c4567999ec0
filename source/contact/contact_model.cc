// The library's one Registry<ContactModel> (contact_model.h), compiled here
// so that the interface builds with the library before any model exists.
#include <perideal/contact/contact_model.h>

namespace perideal
{
  template class Registry<ContactModel>;
} // namespace perideal

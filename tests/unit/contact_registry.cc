// Registry<ContactModel> (include/perideal/contact/contact_model.h): a contact
// model is one registered file. This program registers a toy model the way a
// model file would, and passes if the registry holds it and creates it by
// name, and if a second registration under the same name is then refused at
// the next use, naming the name.

#include <perideal/contact/contact_model.h>

#include <iostream>
#include <string>

namespace
{
  using namespace dealii;
  using namespace perideal;

  /// A linear repulsion within a fixed radius.
  class ToyContact : public ContactModel
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Contact radius", "1", Patterns::Double(0), "Reach.");
    }
    void
    parse_parameters(ParameterHandler &prm, const std::string &) override
    {
      radius = prm.get_double("Contact radius");
    }
    double
    contact_radius() const override
    {
      return radius;
    }
    double
    stiffness(const double, const double) const override
    {
      return 1;
    }
    void
    compute_force(const ContactPoints &, const unsigned int *, const unsigned int *, const std::size_t,
                  ContactOutput &) const override
    {}

  private:
    double radius = 0;
  };

  PERIDEAL_REGISTER(ContactModel, ToyContact, "Toy", "a test-local contact model")
} // namespace

int
main()
{
  auto &registry = Registry<ContactModel>::instance();
  int   failures = 0;
  const auto check = [&](const bool ok, const std::string &what) {
    std::cout << (ok ? "PASS: " : "FAIL: ") << what << "\n";
    failures += ok ? 0 : 1;
  };

  const std::string names = "|" + registry.names() + "|";
  check(names.find("|Toy|") != std::string::npos, "the registry holds the toy: '" + registry.names() + "'");
  {
    ParameterHandler prm;
    registry.get("Toy", "test").declare(prm);
    prm.set("Contact radius", "0.25");
    auto model = registry.create("Toy", "test");
    model->parse_parameters(prm, "test");
    check(model->contact_radius() == 0.25, "create(\"Toy\") makes the model, which reads its keys");
  }

  registry.add({"Toy", "a second model named Toy", &ToyContact::declare_parameters,
                [] { return std::unique_ptr<ContactModel>(new ToyContact()); }});
  try
    {
      registry.names();
      check(false, "a second registration of 'Toy' is refused");
    }
  catch (const dealii::ExceptionBase &e)
    {
      check(std::string(e.what()).find("two plugins are registered under the name 'Toy'") != std::string::npos,
            "a second registration of 'Toy' is refused at the next use, naming it");
    }
  return failures == 0 ? 0 : 1;
}

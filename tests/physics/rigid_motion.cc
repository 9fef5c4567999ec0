// Rigid motions give zero internal force (PMB and LPS).
//
// A rigid motion y = Q x + c keeps every bond length, so every bond's
// extension is zero up to round-off and so are the force density, the LPS
// dilatation and the strain energy density, at every point, surface points
// included. The force is measured against the force scale of a small strain,
//   f_ref = K * 1e-3 / horizon
// (the force density a strain of 1e-3 that varies over one horizon gives), and
// the dilatation against 1e-3. Round-off in |y_j - y_i| is about 1e-16 |y|, a
// stretch of ~1e-15 against 1e-3: the bound 1e-10 leaves four orders of margin
// and still catches any real force (a wrong sign or a missing term gives O(1)).
//
// The box has different spacings along x, y and z and is off the origin, so
// the rotations move points by O(1) (the 90 degree one by up to ~1.8).
//
// Objectivity: a deformed state y0 = x + u0 (non-affine, |grad u0| ~ 1e-2)
// and the same state rotated, y1 = Q y0 + c, must give f1 = Q f0 and the
// same dilatation and energy density at every point (a force along the
// reference bond instead of the deformed one fails this). Bound: max |f1 -
// Q f0| below 1e-10 of the force scale above, |theta1 - theta0| below 1e-10
// of 1e-3, |W1 - W0| below 1e-10 of K 1e-6.

#include "harness.h"

using namespace pdtest;

int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    const double K      = 2.5;
    const double strain = 1e-3;
    const double f_ref  = K * strain / rigid_box::horizon;
    const double tol    = 1e-10;

    const Tensor<2, 3> I = unit_symmetric_tensor<3>();
    const Tensor<1, 3> c = rigid_box::translation, axis = rigid_box::axis;
    Tensor<1, 3>       axis_z;
    axis_z[2] = 1;
    const std::vector<RigidMotion> motions = {
      {"translation", I, c},
      {"rotation 90 deg about z", rotation(axis_z, M_PI / 2), Tensor<1, 3>()},
      {"rotation 90 deg about (1,-2,3) + translation", rotation(axis, M_PI / 2), c},
      {"rotation 1e-3 rad about (1,-2,3)", rotation(axis, 1e-3), Tensor<1, 3>()},
      {"rotation 2.5 rad about (1,-2,3) + translation", rotation(axis, 2.5), c}};

    const std::vector<MaterialSpec> materials = {
      {"PMB", {{"Density", "1.3"}, {"Bulk modulus", "2.5"}}},
      {"LPS", {{"Density", "1.3"}, {"Bulk modulus", "2.5"}, {"Shear modulus", "1.1"}}},
      {"LPS", {{"Density", "1.3"}, {"Bulk modulus", "2.5"}, {"Shear modulus", "1.1"},
               {"Influence function", "1/r"}}}};

    for (const auto &spec : materials)
      {
        Harness h(comm, rigid_box::lower, rigid_box::upper, rigid_box::cells, rigid_box::horizon, spec);
        const bool lps = spec.model == "LPS";
        std::string name = spec.model;
        if (spec.keys.count("Influence function"))
          name += " (omega = " + spec.keys.at("Influence function") + ")";
        report.line(name + ": " + std::to_string(h.cloud.n_global()) + " points, " +
                    sci(Utilities::MPI::sum(double(h.bonds.n_bonds()), comm), 8) + " bonds");
        for (const auto &m : motions)
          {
            h.set_displacement([&](const Point<3> &x) {
              return Tensor<1, 3>(m.Q * Tensor<1, 3>(x) + m.c - Tensor<1, 3>(x));
            });
            h.evaluate(true);
            double f_max = 0, theta_max = 0, w_max = 0, u_max = 0;
            for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
              {
                f_max = std::max(f_max, h.force_of(i).norm());
                w_max = std::max(w_max, std::abs(h.energy[i]));
                for (unsigned int d = 0; d < 3; ++d)
                  u_max = std::max(u_max, std::abs(h.u.local_element(3 * i + d)));
                if (lps)
                  theta_max = std::max(theta_max, std::abs(h.field("dilatation", i)));
              }
            f_max     = Utilities::MPI::max(f_max, comm);
            theta_max = Utilities::MPI::max(theta_max, comm);
            w_max     = Utilities::MPI::max(w_max, comm);
            u_max     = Utilities::MPI::max(u_max, comm);
            report.line("  " + m.name + " (max |u| " + sci(u_max, 4) + ")");
            report.check("    max |f| / (K 1e-3 / horizon)", f_max / f_ref, f_max / f_ref < tol,
                         "< " + sci(tol));
            // Energy density of a strain of 1e-3 is ~K 1e-6.
            report.check("    max |W| / (K 1e-6)", w_max / (K * strain * strain),
                         w_max / (K * strain * strain) < tol, "< " + sci(tol));
            if (lps)
              report.check("    max |dilatation| / 1e-3", theta_max / strain,
                           theta_max / strain < tol, "< " + sci(tol));
          }

        // Objectivity under a 90 degree rotation plus translation.
        const RigidMotion &m  = motions[2];
        const auto         u0 = non_affine_displacement;
        h.set_displacement(u0);
        h.evaluate(true);
        const unsigned int        n = h.cloud.n_owned();
        std::vector<Tensor<1, 3>> f0(n);
        std::vector<double>       theta0(n), w0(n);
        double                    f0_max = 0;
        for (unsigned int i = 0; i < n; ++i)
          {
            f0[i]     = h.force_of(i);
            w0[i]     = h.energy[i];
            theta0[i] = lps ? h.field("dilatation", i) : 0;
            f0_max    = std::max(f0_max, f0[i].norm());
          }
        h.set_displacement([&](const Point<3> &x) {
          const Tensor<1, 3> y0 = Tensor<1, 3>(x) + u0(x);
          return Tensor<1, 3>(m.Q * y0 + m.c - Tensor<1, 3>(x));
        });
        h.evaluate(true);
        double df = 0, dtheta = 0, dw = 0;
        for (unsigned int i = 0; i < n; ++i)
          {
            df = std::max(df, (h.force_of(i) - m.Q * f0[i]).norm());
            dw = std::max(dw, std::abs(h.energy[i] - w0[i]));
            if (lps)
              dtheta = std::max(dtheta, std::abs(h.field("dilatation", i) - theta0[i]));
          }
        df     = Utilities::MPI::max(df, comm);
        dw     = Utilities::MPI::max(dw, comm);
        dtheta = Utilities::MPI::max(dtheta, comm);
        f0_max = Utilities::MPI::max(f0_max, comm);
        report.line("  objectivity: deformed state (max |f| / f_ref " + sci(f0_max / f_ref, 4) + ") and " +
                    m.name);
        report.check("    max |f1 - Q f0| / (K 1e-3 / horizon)", df / f_ref, df / f_ref < tol, "< " + sci(tol));
        report.check("    max |W1 - W0| / (K 1e-6)", dw / (K * strain * strain),
                     dw / (K * strain * strain) < tol, "< " + sci(tol));
        if (lps)
          report.check("    max |theta1 - theta0| / 1e-3", dtheta / strain, dtheta / strain < tol,
                       "< " + sci(tol));
      }
  });
}

// The CUDA contact solve (device_solve_class.cuh): the friction fixed point around the normal
// solve, as solver.cpp's solve on the host, step for step.

#include "device_solve_class.cuh"

namespace gfmd {

using namespace contact_detail;
using namespace cuda_kernels;
using namespace contact_device;
using namespace device_solve_detail;

SolveInfo CudaSolve::solve(const LoadParams& load, ContactFields& f, const DeviceHooks& hooks, int& total) {
  // solver.cpp's solve: the friction fixed point with Anderson mixing around the normal solve.
  const auto t0 = Clock::now();
  const std::uint64_t transforms0 = transforms_;
  hooks_ = &hooks;
  host_ = &f;
  total_ = &total;
  total = 0;
  last_checkpoint_ = std::chrono::duration<double>(t0.time_since_epoch()).count();
  const std::size_t n = n_;
  for (auto* fld : {&f.pressure, &f.tx, &f.ty})
    if (fld->size() != n) fld->assign(n, 0.0);
  for (auto* fld : {&f.ux, &f.uy, &f.uz, &f.gap}) RealField().swap(*fld);
  f.stick.clear();
  if (!adhesive_) {
    RealField().swap(f.adhesion);
  } else {
    // The adhesive traction of the warm start (none: zero).
    if (f.adhesion.size() != n) f.adhesion.assign(n, 0.0);
    upload(f.adhesion, a_.get());
  }
  SolveInfo info;
  info.stiffness = k_;
  const double tol = sp_.tolerance;
  const double mu = fric_.coefficient;
  if (mu > 0 && deriv_kind_ != fric_.derivative())
    use_derivative(fric_.derivative());  // a previous solve met stick
  upload(f.pressure, p_.get());
  cuda_check(cudaMemset(w_.get(), 0, n * sizeof(double)), "clearing a field");
  PK pk{};
  if (mu == 0.0) {
    std::fill(f.tx.begin(), f.tx.end(), 0.0);
    std::fill(f.ty.begin(), f.ty.end(), 0.0);
    if (adhesive_) {
      pk = solve_adhesive(load, tol, info, false, -1);
    } else {
      {
        const Phase ph(this, 0);
        pk = solve_normal(load, true, tol, sp_.max_iterations);
      }
      info.converged = pk.converged;
      info.status = pk.converged ? "converged" : "not converged: iteration limit reached";
    }
  } else {
    upload(f.tx, tx_.get());
    upload(f.ty, ty_.get());
    double* ftx = tx_.get();
    double* fty = ty_.get();
    double* tx = ntx_.get();
    double* ty = nty_.get();
    unsigned char* in_supp = in_supp_.get();
    unsigned char* flags = flags_.get();
    std::uint32_t* supp = supp_.get();
    // The support: points where the iterate or its image has been non-zero (solver.cpp),
    // listed in order of entry, each entry's points in grid order.
    const auto add_support = [&](bool warm) {
      launch_each(n, [=] __device__(std::size_t i) {
        flags[i] = warm ? (ftx[i] != 0.0 || fty[i] != 0.0)
                        : joins_support_dev(in_supp[i], tx[i], ty[i], ftx[i], fty[i]);
      });
      std::size_t sel = select_work_.size();
      thrust::counting_iterator<std::uint32_t> idx(0);
      cuda_check(cub::DeviceSelect::Flagged(select_work_.get(), sel, idx, flags, supp + supp_len_,
                                            nsel_.get(), static_cast<std::int64_t>(n)),
                 "support selection");
      std::uint32_t added = 0;
      cuda_check(cudaMemcpy(&added, nsel_.get(), sizeof added, cudaMemcpyDeviceToHost), "support selection");
      launch_each(n, [=] __device__(std::size_t i) {
        if (flags[i]) in_supp[i] = 1;
      });
      supp_len_ += added;
    };
    cuda_check(cudaMemset(in_supp, 0, n), "clearing the support");
    supp_len_ = 0;
    add_support(true);
    std::optional<DeviceAnderson> mixer;
    int depth = sp_.anderson;  // deepened once where the fixed point stalls (as on the host)
    if (sp_.anderson > 0) {
      if (sp_.anderson > kMaxDepth)
        throw InputError("solver.anderson",
                         "the CUDA backend mixes at most " + std::to_string(kMaxDepth) + " steps");
      info.history_depth = depth;
      mixer.emplace(sp_.anderson, 2 * n, &bytes_);
      mixer->resize(2 * supp_len_);
    }
    double err = 1.0;
    std::vector<double> hist_change, hist_force;
    const auto dir = direction();
    const double dir_x = dir.first, dir_y = dir.second;
    FrictionSteps steps(!fric_.regularized() && fric_.rolling(),
                        !fric_.slip_derivative && deriv_kind_ == SlipDerivative::Spectral);
    bool tangential_ok = !steps.stick_mode();
    double stick_now = 0.0;
    bool map_changed = false;  // the slip derivative turned in this friction step (solver.cpp)
    have_z_ = false;
    double omega = sp_.mixing;
    info.status = "not converged: friction fixed point did not settle";
    SolveInfo adhesive_step;  // with adhesion: the last friction step's adhesive solve
    bool pulled_off = false;  // it found the load beyond what the adhesion holds
    for (int outer = 0; outer < sp_.max_outer; ++outer) {
      info.outer_iterations = outer + 1;
      {
        const Phase ph(this, 1);
        friction_normal_displacement();
      }
      const double inner_tol = std::max(tol, std::min(1e-3, 0.1 * err));
      const int budget = sp_.max_iterations - total;
      if (budget <= 0) {
        info.status = "not converged: iteration limit reached";
        break;
      }
      if (adhesive_) {
        // The adhesive normal problem under the friction's normal displacement (w_); its
        // traction a_ is kept from step to step (the warm start of the next), as on the host.
        adhesive_step = SolveInfo{};
        pk = solve_adhesive(load, inner_tol, adhesive_step, true, budget);
        info.adhesion_steps += adhesive_step.adhesion_steps;
        info.elastic_energy = adhesive_step.elastic_energy;
        info.adhesive_energy = adhesive_step.adhesive_energy;
        info.energy = adhesive_step.energy;
        if (adhesive_step.no_state) {  // beyond the pull-off
          info.status = adhesive_step.status;
          pulled_off = true;
          break;
        }
        // The law's bound reads the repulsion p + a (in ad_, free after the adhesive steps); the
        // gap spread used s2/s3: the tractions' spectra again for the slip pass.
        const double* pp = p_.get();
        const double* aa = a_.get();
        double* rep = ad_.get();
        launch_each(n, [=] __device__(std::size_t i) { rep[i] = pp[i] + aa[i]; });
        if (!steps.stick_mode()) {
          forward(tx_.get(), s2_.get());
          forward(ty_.get(), s3_.get());
        }
      } else {
        const Phase ph(this, 0);
        pk = solve_normal(load, false, inner_tol, budget);
      }
      std::array<double, 4> dn{};
      if (!steps.stick_mode()) {
        const Phase ph(this, 1);
        dn = slip_tractions();
        steps.full_slip_step(dn[3]);
      } else {
        if (!have_z_) {
          cuda_check(cudaMemcpy(tx, ftx, n * sizeof(double), cudaMemcpyDeviceToDevice), "copy");
          cuda_check(cudaMemcpy(ty, fty, n * sizeof(double), cudaMemcpyDeviceToDevice), "copy");
        }
        const double ttol = std::max(0.1 * tol, std::min(1e-3, kTangentialTolFactor * err));
        const Phase ph(this, 2);
        const auto tr = solve_tangential(ttol, sp_.max_tangential);
        info.tangential_iterations += tr.iterations;
        tangential_ok = tr.converged && ttol <= 0.1 * tol;
        const double* pp = law_pressure();
        const double* zxs = zx_.get();
        const double* zys = zy_.get();
        const FrictionLaw law = fric_.law;
        const auto c = red_.run<4>(n, [=] __device__(std::size_t i, double* acc) {
          add_change_dev(acc, in_supp[i], tx[i], ty[i], ftx[i], fty[i]);
          const double r = law.bound(mu, pp[i], 0.0);  // the friction disc's radius
          if (r > 0 && zxs[i] * zxs[i] + zys[i] * zys[i] < r * r) acc[3] += 1.0;
        });
        dn = {c[0], c[1], c[2], 0.0};
        stick_now = c[3];
        if (steps.settles_upwind(stick_now)) {
          use_derivative(SlipDerivative::Upwind2);
          have_z_ = false;
          tangential_ok = false;
          map_changed = true;
        }
      }
      err = dn[1] > 0 ? dn[0] / dn[1] : 0.0;
      require_finite(err, "the friction traction", total);
      info.friction_error = err;
      hist_change.push_back(err);
      const double ddx = dir_x, ddy = dir_y;
      hist_force.push_back(red_.run<1>(
          n, [=] __device__(std::size_t i, double* acc) { acc[0] += ddx * tx[i] + ddy * ty[i]; })[0]);
      if (hooks.progress && *hooks.progress) (*hooks.progress)(Progress{total, outer + 1, err});
      poll(true);
      const bool done = err < tol && pk.converged && inner_tol <= tol && tangential_ok;
      if (steps.turns_back(done, stick_now)) {
        use_derivative(SlipDerivative::Spectral);
        have_z_ = false;
        tangential_ok = false;
        map_changed = true;
      } else if (done) {
        tx_.swap(ntx_);
        ty_.swap(nty_);
        info.converged = true;
        info.status = "converged";
        break;
      }
      const FrictionSteps::Next next = steps.after(err, outer, !fric_.regularized());
      if (next == FrictionSteps::Next::HandOver) {
        if (steps.upwind()) use_derivative(SlipDerivative::Upwind2);
        tangential_ok = false;
        if (mixer) mixer->restart();
        continue;
      }
      if (next == FrictionSteps::Next::Damp && mixer && deepened_history(sp_.anderson, depth) != depth) {
        // As on the host: a longer mixing history first, started afresh.
        depth = deepened_history(sp_.anderson, depth);
        mixer.emplace(depth, 2 * n, &bytes_);
        mixer->resize(2 * supp_len_);
        info.history_depth = depth;
      } else if (next == FrictionSteps::Next::Damp) {
        omega = damped_mixing(omega, sp_.mixing, hist_change);
        if (mixer) mixer->clear_history();
        if (omega == 0.0) {
          tx_.swap(ntx_);
          ty_.swap(nty_);
          info.status = "not converged: oscillating (friction fixed point does not settle even with damping)";
          break;
        }
      }
      if (dn[2] > 0) {
        const Phase ph(this, 4);
        add_support(false);
        if (mixer) mixer->resize(2 * supp_len_);
      }
      if (map_changed) {
        // As on the host: the image becomes the iterate, the mixing starts afresh.
        map_changed = false;
        cuda_check(cudaMemcpy(ftx, tx, n * sizeof(double), cudaMemcpyDeviceToDevice), "copy");
        cuda_check(cudaMemcpy(fty, ty, n * sizeof(double), cudaMemcpyDeviceToDevice), "copy");
        if (mixer) mixer->restart();
        continue;
      }
      double* zx = zx_.get();
      double* zy = zy_.get();
      const bool follow = steps.stick_mode();
      const std::size_t len = supp_len_;
      if (!mixer) {
        const double om = omega;
        launch_each(len, [=] __device__(std::size_t j) {
          const std::uint32_t i = supp[j];
          const double ox = ftx[i], oy = fty[i];
          ftx[i] = ox + om * (tx[i] - ox);
          fty[i] = oy + om * (ty[i] - oy);
          if (follow) {
            zx[i] += ftx[i] - tx[i];
            zy[i] += fty[i] - ty[i];
          }
        });
        continue;
      }
      const Phase ph(this, 3);
      mixer->step(red_, omega, MixTarget{ftx, fty, tx, ty, supp});
      if (follow)
        launch_each(len, [=] __device__(std::size_t j) {
          const std::uint32_t i = supp[j];
          zx[i] += ftx[i] - tx[i];
          zy[i] += fty[i] - ty[i];
        });
    }
    if (!info.converged && !pulled_off && info.status.rfind("not converged: iteration limit", 0) != 0)
      info.status +=
          "; " + friction_history_evidence(hist_change, hist_force,
                                           info.status.find("even with damping") != std::string::npos);
    if (!info.converged && !pulled_off && !adhesive_step.converged && !adhesive_step.status.empty())
      info.status += "; the last adhesive solve: " + adhesive_step.status;
    if (!info.converged && !pulled_off && fric_.law.kind == FrictionLawKind::Tresca &&
        mu > kTrescaSteepCoefficient)
      info.status += kTrescaSteepHint;
    if (!fric_.regularized()) f.stick.assign(n, 0);
    if (steps.stick_mode() && have_z_) {
      const double* p = law_pressure();
      const double* zx = zx_.get();
      const double* zy = zy_.get();
      unsigned char* fl = flags_.get();
      const FrictionLaw law = fric_.law;
      const auto ns = red_.run<1>(n, [=] __device__(std::size_t i, double* acc) {
        const double r = law.bound(mu, p[i], 0.0);
        const bool s = r > 0 && zx[i] * zx[i] + zy[i] * zy[i] < r * r;
        fl[i] = s ? 1 : 0;
        if (s) acc[0] += 1.0;
      })[0];
      cuda_check(cudaMemcpy(f.stick.data(), fl, n, cudaMemcpyDeviceToHost), "reading the stick mask");
      info.stick_points = static_cast<std::size_t>(ns);
    }
    if (!pk.converged && info.converged) {
      info.converged = false;
      info.status = "not converged: iteration limit reached";
    }
  }
  info.iterations = total;
  info.slip_derivative = deriv_kind_;
  info.pk_error = pk.error;
  info.approach = pk.delta;
  // The displacements of (tau, -p) and the gap, then everything back to the host.
  {
    const Phase ph(this, 6);
    forward(p_.get(), s1_.get());
    const bool fr = mu > 0;
    if (fr) {
      forward(tx_.get(), s2_.get());
      forward(ty_.get(), s3_.get());
    }
    const double scale = 1.0 / static_cast<double>(n_);
    const ComplianceMode* md = modes_.get();
    cufftDoubleComplex* a = s1_.get();
    cufftDoubleComplex* b = s2_.get();
    cufftDoubleComplex* c = s3_.get();
    launch_each(ns_, [=] __device__(std::size_t k) {
      const ComplianceMode m = md[k];
      const cufftDoubleComplex z = cscale(-scale, a[k]);
      const cufftDoubleComplex x = fr ? cscale(scale, b[k]) : cufftDoubleComplex{0.0, 0.0};
      const cufftDoubleComplex y = fr ? cscale(scale, c[k]) : cufftDoubleComplex{0.0, 0.0};
      cufftDoubleComplex ux, uy;
      inplane(m, x, y, z, ux, uy);
      const cufftDoubleComplex ix = times_i(m.cxz, x), iy = times_i(m.cyz, y);
      a[k] = {m.czz * z.x - ix.x - iy.x, m.czz * z.y - ix.y - iy.y};
      b[k] = ux;
      c[k] = uy;
    });
    backward(s1_.get(), cg_g_.get());
    backward(s2_.get(), cg_t_.get());
    backward(s3_.get(), cg_r_.get());
    if (adhesive_ && fr) {
      // The elastic energy with the tractions' share: 1/2 sum (tau.u_t - p u_z) dA (the adhesive
      // steps counted the normal part alone), as on the host.
      const double *uz = cg_g_.get(), *ux = cg_t_.get(), *uy = cg_r_.get();
      const double *px = p_.get(), *qx = tx_.get(), *qy = ty_.get();
      const double e = 0.5 * grid_.cell_area() * red_.run<1>(n, [=] __device__(std::size_t i, double* acc) {
        acc[0] += qx[i] * ux[i] + qy[i] * uy[i] - px[i] * uz[i];
      })[0];
      info.energy += e - info.elastic_energy;
      info.elastic_energy = e;
    }
    download(cg_g_.get(), f.uz);
    download(cg_t_.get(), f.ux);
    download(cg_r_.get(), f.uy);
    if (fr) {
      download(tx_.get(), f.tx);
      download(ty_.get(), f.ty);
    }
    download(p_.get(), f.pressure);
    if (adhesive_) {
      download(a_.get(), f.adhesion);
      if (spread_out_) download(aspread_.get(), *spread_out_);
    }
  }
  info.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (profile_) {
    const auto& t = phase_s_;
    std::fprintf(stderr,
                 "cuda profile: %.4f s in all; normal %.4f (%d iterations), slip %.4f, stick-slip %.4f, "
                 "mixing %.4f, support %.4f, results %.4f, other %.4f; %llu transforms\n",
                 info.wall_time_s, t[0], info.iterations, t[1], t[2], t[3], t[4], t[6],
                 info.wall_time_s - (t[0] + t[1] + t[2] + t[3] + t[4] + t[6]),
                 static_cast<unsigned long long>(transforms_ - transforms0));
    phase_s_.fill(0.0);
  }
  info.transforms = transforms_ - transforms0;
  hooks_ = nullptr;
  host_ = nullptr;
  total_ = nullptr;
  return info;
}

}  // namespace gfmd

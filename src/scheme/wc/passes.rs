//! The two gather passes of a weakly compressible rate evaluation (see the parent module).

use super::*;

impl<K: Kernel, R: Rheology> WcCore<K, R> {
    /// Pass 1 (a gather): velocity gradient (Fang eq. 23), continuity (eq. 26), stresses, and
    /// the kernel values of every pair inside the support, cached for pass 2.
    pub(super) fn pass1(&mut self, fl: &Fluid) {
        let nf = fl.len();
        let mass = fl.mass;
        self.pairs.resize_for(&self.nlist);
        self.kappa.resize(nf, Mat2::zeros());
        self.drho.resize(nf, 0.0);
        let (kernel, model, p, art, evss) =
            (&self.kernel, &self.model, &self.p, &self.art, self.evss);
        let (ax, av, avol, tau_p) = (&self.all_x, &self.all_v, &self.all_vol, &self.tau_p);
        let (nlist, dom) = (&self.nlist, &self.p.domain);
        let r2max = kernel.radius().powi(2);
        let need_hess = art.needs_hessian();
        let laplacian = self.laplacian();
        let js = nlist.split_mut(&mut self.pairs.j);
        let gs = nlist.split_mut(&mut self.pairs.grad);
        let ws = nlist.split_mut(&mut self.pairs.w);
        (
            js,
            gs,
            ws,
            &mut self.pairs.len[..],
            &mut self.kappa[..],
            &mut self.drho[..],
            &mut self.all_sigma[..nf],
            &mut self.all_art[..nf],
            &mut self.all_hess[..nf],
            &mut self.all_mu[..nf],
        )
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .enumerate()
            .for_each(
                |(i, (js, gs, ws, len, kappa_i, drho_i, sigma_i, art_i, hess_i, mu_i))| {
                    let (xi, vi) = (ax[i], av[i]);
                    let mut kin = Kinematics::default();
                    let mut hess = Mat2::zeros();
                    let mut k = 0;
                    for &j in nlist.of(i) {
                        let ju = j as usize;
                        if ju == i {
                            continue;
                        }
                        let xij = dom.delta(&xi, &ax[ju]);
                        let r2 = xij.norm_squared();
                        if r2 >= r2max {
                            continue;
                        }
                        let r = r2.sqrt();
                        let (w, dw_r) = kernel.w_and_dw_over_r(r);
                        let grad = xij * dw_r;
                        js[k] = j;
                        gs[k] = grad;
                        ws[k] = w;
                        k += 1;
                        kin.add_pair(&(vi - av[ju]), &grad, avol[ju]);
                        if need_hess {
                            hess += artificial::kernel_hessian(kernel, &xij, r2);
                        }
                    }
                    *len = k as u32;
                    *kappa_i = kin.kappa;
                    *drho_i = kin.continuity * mass;
                    *hess_i = hess;
                    let eta = model.solvent_viscosity(&kin.kappa);
                    *mu_i = evss.viscous_viscosity(eta);
                    let tau = R::ELASTIC.then(|| &tau_p[i]);
                    let sigma = stress::assemble(
                        p.eos.pressure(fl.rho[i]),
                        eta,
                        &kin.kappa,
                        tau,
                        &evss,
                        laplacian,
                    );
                    *sigma_i = sigma;
                    *art_i = art.of_particle(&sigma, fl.rho[i], &hess);
                },
            );
    }

    /// Pass 2 (a gather over the cached pairs): momentum (Fang eq. 27, Ren eq. 21) with
    /// artificial viscosity (Fang eqs. 30-37, Ren eq. 19) and artificial stress (Fang eq. 38,
    /// Ren eq. 20a); with EVSS, Morris' viscous Laplacian.
    pub(super) fn pass2(&mut self, fl: &Fluid) -> StageReport {
        let nf = fl.len();
        let mass = fl.mass;
        self.acc.resize(nf, Vec2::zeros());
        self.wall_acc.resize(nf, Vec2::zeros());
        {
            let p = &self.p;
            let (ax, av, arho, asr2, aart, amu) = (
                &self.all_x,
                &self.all_v,
                &self.all_rho,
                &self.all_sr2,
                &self.all_art,
                &self.all_mu,
            );
            let (pairs, nlist, dom) = (&self.pairs, &self.nlist, &self.p.domain);
            let h = self.kernel.h();
            let art = &self.art;
            let use_art = art.is_on();
            let morris = self.laplacian();
            let eta2 = MORRIS_ETA2 * h * h;
            (&mut self.acc[..], &mut self.wall_acc[..])
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .enumerate()
                .for_each(|(i, (acc_i, wall_i))| {
                    let (xi, vi, rhoi, si, ri) = (ax[i], av[i], arho[i], asr2[i], aart[i]);
                    let mut a = Vec2::zeros();
                    let mut aw = Vec2::zeros();
                    for k in pairs.range(nlist, i) {
                        let j = pairs.j[k] as usize;
                        let mut t = si + asr2[j];
                        let xij = dom.delta(&xi, &ax[j]);
                        let vij = vi - av[j];
                        let r2 = xij.norm_squared();
                        let pi = artificial::viscosity(
                            p.alpha,
                            p.beta,
                            h,
                            p.eos.c,
                            0.5 * (rhoi + arho[j]),
                            &vij,
                            &xij,
                            r2,
                        );
                        t[(0, 0)] -= pi;
                        t[(1, 1)] -= pi;
                        if use_art {
                            let rsum = ri + aart[j];
                            if rsum != Mat2::zeros() {
                                t += rsum * art.pair_factor(pairs.w[k], r2);
                            }
                        }
                        let grad = pairs.grad[k];
                        let mut contrib = t * grad;
                        if morris {
                            contrib += stress::morris_pair(
                                &vij,
                                &xij,
                                &grad,
                                amu[i] + amu[j],
                                rhoi,
                                arho[j],
                                r2,
                                eta2,
                            );
                        }
                        if j < nf {
                            a += contrib;
                        } else {
                            aw += contrib;
                        }
                    }
                    *wall_i = aw * mass;
                    *acc_i = (a + aw) * mass + p.gravity;
                });
        }
        // Sequential, fixed-order reductions.
        let mut report = StageReport::default();
        for (a, aw) in self.acc.iter().zip(&self.wall_acc) {
            report.max_acc = report.max_acc.max(a.norm());
            report.wall_on_fluid += aw * mass;
        }
        report
    }
}

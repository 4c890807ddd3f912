//! The two gather passes of a rate evaluation in any dimension, over nalgebra's types: the sums
//! of the packed passes (`passes.rs`, the two-dimensional fast path), written plainly, pair by
//! pair. The dimensions without packed passes run these ([`super::WcSpace`]).

use super::*;

impl<K: Kernel<N>, R: Rheology, const N: usize> WcCore<K, R, N>
where
    Const<N>: Dim + WcSpace<N>,
{
    /// Pass 1 ([`super::WcSpace::pass1`]) pair by pair.
    pub(super) fn pass1_plain(&mut self, fl: &Fluid<N>) {
        let nf = fl.len();
        let mass = fl.mass;
        self.pairs.resize_for(&self.nlist);
        self.kappa.resize(nf, Tensor::zeros());
        self.drho.resize(nf, 0.0);
        let laplacian = self.laplacian();
        let (kernel, model, p, art, evss) =
            (&self.kernel, &self.model, &self.p, &self.art, self.evss);
        let (ax, av, arho, avol) = (&self.all_x, &self.all_v, &self.all_rho, &self.all_vol);
        let (tau_p, nlist, dom) = (&self.tau_p, &self.nlist, p.domain);
        let (h, r2max) = (kernel.h(), kernel.radius().powi(2));
        let (art_on, hessian) = (art.is_on(), art.needs_hessian());
        let js = nlist.split_mut(&mut self.pairs.j);
        let gs = nlist.split_mut(&mut self.pairs.grad);
        let ps = nlist.split_mut(&mut self.pairs.pi);
        let fs = nlist.split_mut(&mut self.pairs.f);
        (
            (js, gs, ps, fs),
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
                |(i, ((js, gs, ps, fs), len, kappa_i, drho_i, sigma_i, art_i, hess_i, mu_i))| {
                    let (xi, vi, rhoi) = (ax[i], av[i], arho[i]);
                    let mut k = 0;
                    let mut kin = Kinematics::default();
                    let mut hess = Tensor::zeros();
                    for &j in nlist.of(i) {
                        let ju = j as usize;
                        let xij = dom.delta(&xi, &ax[ju]);
                        let r2 = xij.norm_squared();
                        if ju == i || r2 >= r2max {
                            continue;
                        }
                        let (w, dw_r) = kernel.w_and_dw_over_r(r2.sqrt());
                        let grad = xij * dw_r;
                        let vij = vi - av[ju];
                        let rho_mean = 0.5 * (rhoi + arho[ju]);
                        js[k] = j;
                        gs[k] = grad;
                        ps[k] = artificial::viscosity_of_dot(
                            p.alpha,
                            p.beta,
                            h,
                            p.eos.c,
                            rho_mean,
                            vij.dot(&xij),
                            r2,
                        );
                        fs[k] = if art_on { art.pair_factor(w, r2) } else { 0.0 };
                        k += 1;
                        kin.add_pair(&vij, &grad, avol[ju]);
                        if hessian {
                            hess += artificial::kernel_hessian(kernel, &xij, r2);
                        }
                    }
                    *len = k as u32;
                    *kappa_i = kin.kappa;
                    *drho_i = kin.continuity * mass;
                    *hess_i = hess;
                    let tau = R::ELASTIC.then(|| &tau_p[i]);
                    (*mu_i, *sigma_i, *art_i) = particle_stress(
                        model, p, art, &evss, laplacian, &kin.kappa, tau, fl.rho[i], &hess,
                    );
                },
            );
    }

    /// Pass 2 ([`super::WcSpace::pass2`]) pair by pair.
    pub(super) fn pass2_plain(&mut self, fl: &Fluid<N>) {
        let nf = fl.len();
        let mass = fl.mass;
        self.acc.resize(nf, Vector::zeros());
        self.wall_acc.resize(nf, Vector::zeros());
        let wall_ends: Vec<u32> = self.wall_ranges.iter().map(|r| r.end as u32).collect();
        let nw = wall_ends.len();
        self.wall_split
            .resize(if nw > 1 { nf * nw } else { nf }, Vector::zeros());
        let (laplacian, art_on) = (self.laplacian(), self.art.is_on());
        let p = &self.p;
        let dom = p.domain;
        let (ax, av, arho, amu) = (&self.all_x, &self.all_v, &self.all_rho, &self.all_mu);
        let (asig, aart) = (&self.all_sigma, &self.all_art);
        let (pairs, nlist) = (&self.pairs, &self.nlist);
        let h = self.kernel.h();
        let eta2 = MORRIS_ETA2 * h * h;
        (
            &mut self.acc[..],
            &mut self.wall_acc[..],
            self.wall_split.par_chunks_mut(if nw > 1 { nw } else { 1 }),
        )
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .enumerate()
            .for_each(|(i, (acc_i, wall_i, split_i))| {
                let range = pairs.range(nlist, i);
                let (jj, gg) = (&pairs.j[range.clone()], &pairs.grad[range.clone()]);
                let (pp, ff) = (&pairs.pi[range.clone()], &pairs.f[range]);
                let si = asig[i] / (arho[i] * arho[i]);
                // Ascending lists: fluid neighbours first, then virtual ones.
                let split = jj.partition_point(|&j| (j as usize) < nf);
                let sum = |from: usize, to: usize| {
                    let mut a = Vector::<N>::zeros();
                    for k in from..to {
                        let j = jj[k] as usize;
                        let mut t = si + asig[j] / (arho[j] * arho[j]);
                        t -= Tensor::identity() * pp[k];
                        if art_on {
                            t += (aart[i] + aart[j]) * ff[k];
                        }
                        a += t * gg[k];
                        if laplacian {
                            let xij = dom.delta(&ax[i], &ax[j]);
                            let (vij, mu) = (av[i] - av[j], amu[i] + amu[j]);
                            let r2 = xij.norm_squared();
                            a += stress::morris_pair(
                                &vij, &xij, &gg[k], mu, arho[i], arho[j], r2, eta2,
                            );
                        }
                    }
                    a
                };
                book_particle(
                    sum,
                    jj,
                    split,
                    &wall_ends,
                    mass,
                    p.gravity,
                    (acc_i, wall_i, split_i),
                );
            });
    }
}

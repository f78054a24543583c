"""stelaCSF written out again from the authors' MATLAB, independently of acuity's C++.

Source: gfxdisp/stelaCSF at 052b15e, matlab/CSF_stelaCSF.m (sensitivity, get_sust_trans_resp,
csf_achrom, get_default_par) and matlab/CSF_base.m (get_lum_dep). Plain numpy in the linear domain,
as the MATLAB computes it (no log domain, no clamping), so that it checks acuity's log-domain code.
tests/python/test_stela.py checks this transcription against the authors' code run under Octave
(shared/reference/vision-models.md section 4.1) and acuity against it.

Run as a script, it prints the expected values written into tests/test_models.cpp
(Published.StelaCsfTranscription):  /usr/bin/python3 tests/python/stela_reference.py
"""
import numpy as np

# get_default_par(): fit "stela-csf_all_2022-04-16_16-48"
SUST_S_MAX = [68.9501, 59.5023, 0.164274, 7.54866e-07, 7.77268e09]
SUST_F_MAX = [1.62144, 36.6565, 0.255823]
SUST_BW, SUST_A = 0.000219263, 0.103686
TRANS_S_MAX = [0.500846, 57.3469]
TRANS_F_MAX = [0.0267489]
TRANS_BW, TRANS_A = 1.75147, 0.000273289
SIGMA_TRANS, SIGMA_SUST = 0.12314, 5.79336
ECC_DROP, ECC_DROP_NASAL = 0.0296662, 0.0113638
ECC_DROP_F, ECC_DROP_F_NASAL = 0.0190062, 0.0193858


def lum_dep(pars, lum):
    """CSF_base.get_lum_dep: the luminance dependence by the number of parameters."""
    if len(pars) == 1:
        return pars[0] * np.ones_like(lum)
    if len(pars) == 2:
        return pars[1] * lum ** pars[0]
    if len(pars) == 3:
        return pars[0] * (1 + pars[1] / lum) ** (-pars[2])
    if len(pars) == 5:
        return pars[0] * (1 + pars[1] / lum) ** (-pars[2]) * (1 - (1 + pars[3] / lum) ** (-pars[4]))
    raise ValueError("not implemented")


def sust_trans_resp(omega):
    """get_sust_trans_resp: beta_sust 1.3314, omega_0 5 Hz, beta_trans 0.1898."""
    r_sust = np.exp(-omega ** 1.3314 / SIGMA_SUST)
    r_trans = np.exp(-np.abs(omega ** 0.1898 - 5 ** 0.1898) ** 2 / SIGMA_TRANS)
    return r_sust, r_trans


def csf_achrom(freq, area, lum, s_max, f_max, bw, a):
    """csf_achrom: truncated log-parabola, Rovamo's area model (A0 270, f0 0.65), times freq."""
    freq, area, lum = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (freq, area, lum)))
    s_max_l = lum_dep(s_max, lum)
    f_max_l = lum_dep(f_max, lum)
    s_lp = 10.0 ** (-(np.log10(freq) - np.log10(f_max_l)) ** 2 / 2.0 ** bw)
    ss = (freq < f_max_l) & (s_lp < 1 - a)
    s_lp = np.where(ss, 1 - a, s_lp)
    a_c = 270.0 / (1 + (freq / 0.65) ** 2)
    return s_max_l * s_lp * np.sqrt(a_c / (1 + a_c / area)) * freq


def sensitivity(rho, omega, lum, area, ecc=0.0, vis_field=0.0):
    """CSF_stelaCSF.sensitivity with ps_beta = 1: 1 / threshold luminance contrast."""
    rho, omega, lum, area, ecc, vis_field = (np.asarray(x, dtype=float)
                                             for x in (rho, omega, lum, area, ecc, vis_field))
    r_sust, r_trans = sust_trans_resp(omega)
    s = (r_sust * csf_achrom(rho, area, lum, SUST_S_MAX, SUST_F_MAX, SUST_BW, SUST_A) +
         r_trans * csf_achrom(rho, area, lum, TRANS_S_MAX, TRANS_F_MAX, TRANS_BW, TRANS_A))
    alpha = np.minimum(1, np.abs(vis_field - 180) / 90)
    drop = alpha * ECC_DROP + (1 - alpha) * ECC_DROP_NASAL
    drop_f = alpha * ECC_DROP_F + (1 - alpha) * ECC_DROP_F_NASAL
    return s * 10.0 ** (-(drop + rho * drop_f) * ecc)


# Conditions beyond the Octave table: (rho cpd, omega Hz, L cd/m^2, A deg^2, e deg, vis_field deg).
EXTRA = [
    (0.1, 0, 100, 1, 0, 0),       # below the sustained peak: the truncated parabola
    (0.5, 2, 100, 10, 0, 0),      # a low frequency flickering: the transient mechanism
    (4, 20, 100, 1, 0, 0),
    (4, 60, 100, 1, 0, 0),
    (2, 0, 1000, 1, 0, 0),        # high luminance: S_max's second hyperbola
    (2, 0, 10000, 1, 0, 0),
    (2, 0, 0.01, 1, 0, 0),
    (8, 0, 100, 0.01, 0, 0),      # small and large areas
    (1, 0, 100, 1e6, 0, 0),
    (4, 0, 100, 1, 10, 180),      # the nasal meridian
    (4, 0, 100, 1, 10, 90),       # superior (temporal constants)
    (4, 0, 100, 1, 10, 240),      # inferior as the README gives it (alpha = 2/3)
    (1, 3, 30, 4, 40, 180),
    (16, 1, 100, 2, 2, 0),
]

if __name__ == "__main__":
    for cond in EXTRA:
        print("{%s, %.17g}," % (", ".join(repr(float(x)) for x in cond), float(sensitivity(*cond))))

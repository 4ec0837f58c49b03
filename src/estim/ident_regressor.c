/* Regression signals of method §2 through identical filters.  See
 * ident_regressor.h. */
#include "ident_regressor.h"

#include <string.h>

#include "estim_bfp.h"

bw_filter_status_t ident_regressor_init(ident_regressor_t *r, float wc_rad_s,
                                        uint16_t n_pass, float Ts_s,
                                        float w_base_rad_s)
{
    bw_filter_status_t st;
    memset(r, 0, sizeof *r);
    st = bw_filter_init(&r->f_im, wc_rad_s, n_pass, Ts_s, w_base_rad_s);
    if (st != BW_FILTER_OK) {
        memset(r, 0, sizeof *r);
        return st;
    }
    /* identical instances: same gain and delay for every signal (method §5) */
    r->f_it = r->f_im;
    r->f_um = r->f_im;
    r->f_ut = r->f_im;
    r->f_ws_it = r->f_im;
    r->f_ws_im = r->f_im;
    r->f_wr = r->f_im;
    return BW_FILTER_OK;
}

void ident_regressor_reset(ident_regressor_t *r)
{
    bw_filter_reset(&r->f_im, _IQ(0.0));
    bw_filter_reset(&r->f_it, _IQ(0.0));
    bw_filter_reset(&r->f_um, _IQ(0.0));
    bw_filter_reset(&r->f_ut, _IQ(0.0));
    bw_filter_reset(&r->f_ws_it, _IQ(0.0));
    bw_filter_reset(&r->f_ws_im, _IQ(0.0));
    bw_filter_reset(&r->f_wr, _IQ(0.0));
}

/* Scaling/overflow: see ident_regressor.h. */
void ident_regressor_step(ident_regressor_t *r)
{
    /* Park rotation at the mid-period angle (method §7 point 1); rounded
     * products = _IQrmpy bit for bit (estim_bfp.h), |u| < 64 pu */
    r->u_m = iq_rmpy(r->u_alpha, r->cos_mid) + iq_rmpy(r->u_beta, r->sin_mid);
    r->u_t = iq_rmpy(r->u_beta, r->cos_mid) - iq_rmpy(r->u_alpha, r->sin_mid);

    r->f_im.u = r->i_m;
    r->f_it.u = r->i_t;
    r->f_um.u = r->u_m;
    r->f_ut.u = r->u_t;
    /* the products are filtered as single signals (method §7 point 2) */
    r->f_ws_it.u = iq_rmpy(r->ws, r->i_t);     /* Q24*Q24 -> Q24, rounded */
    r->f_ws_im.u = iq_rmpy(r->ws, r->i_m);     /* Q24*Q24 -> Q24, rounded */
    r->f_wr.u = r->wr;

    /* only i_M and i_T need the derivative output */
    bw_filter_step(&r->f_im);
    bw_filter_step(&r->f_it);
    bw_filter_update(&r->f_um);
    bw_filter_update(&r->f_ut);
    bw_filter_update(&r->f_ws_it);
    bw_filter_update(&r->f_ws_im);
    bw_filter_update(&r->f_wr);

    /* eq. 5 (row 2 with +, method §2) */
    r->y1 = r->f_im.dy - r->f_ws_it.y;
    r->y2 = r->f_it.dy + r->f_ws_im.y;
    r->i_mf = r->f_im.y;
    r->u_mf = r->f_um.y;
    r->i_tf = r->f_it.y;
    r->u_tf = r->f_ut.y;
    r->wr_f = r->f_wr.y;
}

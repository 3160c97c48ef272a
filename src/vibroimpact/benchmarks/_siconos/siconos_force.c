/* Siconos plugin for the forcing of src/vibroimpact/_siconos/siconos_peer.py (built by vibroimpact.peer_siconos with the
 * system C compiler): the external force of a 1-DOF LagrangianDS, fExt = cos(pi t + theta) + gbar,
 * with z = [theta, gbar] (the DS's parameter vector).  Signature: Siconos' VectorFunctionOfTime. */
#include <math.h>

void vi_fext(double time, unsigned int n, double *fext, unsigned int nz, double *z)
{
    (void)n;
    (void)nz;
    fext[0] = cos(M_PI * time + z[0]) + z[1];
}

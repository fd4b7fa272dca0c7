/* The forcing f_j cos(omega t) of the N modes, as a Siconos plugin for
 * LagrangianDS::setComputeFExtFunction; z = [omega, f_1, ..., f_N]. */
#include <math.h>

void forcing(double time, unsigned int size, double *fext, unsigned int size_z, double *z)
{
  double c = cos(z[0] * time);
  for (unsigned int j = 0; j < size && j + 1 < size_z; j++)
    fext[j] = z[j + 1] * c;
}

#!/usr/bin/env python3
# The expected values of KFormulaPrecision.ConstantsAreTheNearestDoubleOfTheirExactValue
# (test_k_formula.cpp), computed without CLN: Python's decimal module at 3000 digits, pi by
# Machin's formula in integers, sin and cos by their series after reduction modulo 2*pi, exp and
# ln from decimal (correctly rounded in its context); float() then rounds correctly. Prints each
# value as a hex float, with what Python's math module (the C library) gives. Takes ~10 s.
from decimal import Decimal as D, getcontext
from fractions import Fraction as F
getcontext().prec = 3000
def arctan_inv(x, digits):
    scale = 10**(digits+20); total = term = scale // x; x2 = x*x; n = 1; sign = -1
    while term:
        term //= x2; total += sign * (term // (2*n+1)); sign = -sign; n += 1
    return total
def pi_dec(digits):
    v = 4*(4*arctan_inv(5, digits) - arctan_inv(239, digits))
    return D(v) / D(10**(digits+20))
PI = pi_dec(2900)
def reduce(x):
    x = D(x); k = (x / (2*PI)).to_integral_value(); return x - k*2*PI
def sin(x):
    x = reduce(x); s = t = x; n = 1
    while True:
        t = -t*x*x/((2*n)*(2*n+1)); n += 1
        if abs(t) < D(10)**-2900: return s
        s += t
def cos(x):
    x = reduce(x); s = t = D(1); n = 1
    while True:
        t = -t*x*x/((2*n-1)*(2*n)); n += 1
        if abs(t) < D(10)**-2900: return s
        s += t
def h(v): return float(v).hex() + "  " + repr(float(v))
cases = {
 "sin(1e22)": sin(D(10)**22),
 "sin(1e300)": sin(D(10)**300),
 "cos(1e100)": cos(D(10)**100),
 "cos(1e22)": cos(D(10)**22),
 "tan(1e300)": sin(D(10)**300)/cos(D(10)**300),
 "sin(2^1023)": sin(D(2)**1023),
 "sin(exp(exp(5)))": sin(D(D(5).exp()).exp()),
 "exp(700.5)": D("700.5").exp(),
 "exp(-745.1)": D("-745.1").exp(),
 "exp(-740)": D(-740).exp(),
 "1 - cos(1e-10)": 1 - cos(D("1e-10")),
 "sinh(700)": (D(700).exp() - D(-700).exp())/2,
 "log(3)": D(3).ln(),
 "cos(1e-100) - 1": cos(D("1e-100")) - 1,
 "tanh(300) - 1": (D(300).exp() - D(-300).exp())/(D(300).exp() + D(-300).exp()) - 1,
 "exp(-693148)*exp(693140)": D(-8).exp(),
}
for k, v in cases.items(): print(f"{k:20s} {h(v)}")
import math
print("glibc-ish python math: sin(1e22)", repr(math.sin(1e22)), "sin(2.0**1023)", repr(math.sin(2.0**1023)), "cos(1e22)", repr(math.cos(1e22)))
print("exact decimal of double 1e300:", F(1e300))
print("----")
xs = {"1e300": 1e300, "1e100": 1e100, "2^1023": 2.0**1023, "max": 1.7976931348623157e308, "muller": 6381956970095103 * 2.0**797, "1e22": 1e22}
for name, x in xs.items():
    d = D(F(x).numerator)
    s, c = sin(d), cos(d)
    print(f"{name:8s} sin {h(s)}  math {repr(math.sin(x))}   cos {h(c)} math {repr(math.cos(x))}  exact {F(x).numerator}")

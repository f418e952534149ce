import numpy as np
from scipy.optimize import brentq
from scipy.integrate import solve_ivp
# Q3: Newmark trapezoidal period error
def amp_genalpha(Om, rho):
    am=(2*rho-1)/(rho+1); af=rho/(rho+1); g=0.5-am+af; b=0.25*(1-am+af)**2
    # SDOF a+w^2 d=0, w=1, dt=Om. state (d,v,a) at n -> n+1
    h=Om
    # unknown a1: (1-am)a1+am a0 + (1-af)d1 + af d0 = 0 ; d1=d0+h v0+h^2((0.5-b)a0+b a1); v1=v0+h((1-g)a0+g a1)
    A=np.zeros((3,3))
    for j,e in enumerate(np.eye(3)):
        d0,v0,a0=e
        a1=-(am*a0+(1-af)*(d0+h*v0+h*h*(0.5-b)*a0)+af*d0)/((1-am)+(1-af)*h*h*b)
        d1=d0+h*v0+h*h*((0.5-b)*a0+b*a1); v1=v0+h*((1-g)*a0+g*a1)
        A[:,j]=[d1,v1,a1]
    ev=np.linalg.eigvals(A); ev=ev[np.argsort(-np.abs(np.imag(ev)))]
    lam=ev[0]
    return abs(lam), abs(np.angle(lam))/Om, max(abs(ev))
print("Omega | trapz formula T/T-1 | gen-alpha rho=1 numeric | rho=0.8: T/T-1, spectral radius | rho=0.5")
for Om in [0.01,0.1,0.2,0.5,1.0,2.0]:
    f=Om/(2*np.arctan(Om/2))-1
    r1=amp_genalpha(Om,1.0); r8=amp_genalpha(Om,0.8); r5=amp_genalpha(Om,0.5)
    print(f"{Om:5.2f} | {f:.6e} | {1/r1[1]-1:.6e} |r|={r1[0]:.8f} | {1/r8[1]-1:.4e} {r8[2]:.5f} | {1/r5[1]-1:.4e} {r5[2]:.5f}")
for rho in [0,0.5,0.8,1]:
    print("rho_inf",rho,"spectral radius at Omega=1e4:",round(amp_genalpha(1e4,rho)[2],4))
# Q4: Hunt-Crossley exact restitution: x - ln(1+x) = -e x - ln(1-e x), x=chi v0/K
def e_of_x(x):
    f=lambda e: x-np.log1p(x)+e*x+np.log1p(-e*x)
    return brentq(f,1e-12,min(1-1e-15,1/x-1e-12) if x>1 else 1-1e-15)
def x_exact(e):
    return brentq(lambda x: e_of_x(x)-e,1e-9,1e6)
def sim(x,n=1.5):
    # m=K=v0=1, chi=x
    def rhs(t,y): d,v=y; return [v, -(d**n if d>0 else 0)*(1+x*v)]
    ev=lambda t,y: y[0]; ev.terminal=True; ev.direction=-1
    s=solve_ivp(rhs,(0,100),[1e-14,1.0],events=ev,rtol=1e-11,atol=1e-14,max_step=0.01)
    return -s.y_events[0][0][1]
print("\n e | x=chi*v0/K exact | sim check e (n=1.5) | LN 3(1-e^2)/4 | Flores 8(1-e)/(5e) | Gonthier (1-e^2)/e | HC 3(1-e)/2 | series 3(1-e^2)/(2(1+e^3))")
for e in [0.99,0.95,0.9,0.8,0.7,0.6,0.5,0.4,0.3,0.2,0.1]:
    x=x_exact(e)
    print(f"{e:4.2f} | {x:9.5f} | {sim(x):.5f} | {0.75*(1-e*e):8.5f} | {1.6*(1-e)/e:8.5f} | {(1-e*e)/e:8.5f} | {1.5*(1-e):8.5f} | {1.5*(1-e*e)/(1+e**3):8.5f}")
print("n=1 check e=0.5:",sim(x_exact(0.5),n=1.0))

# fully nonlinear (inextensible) lumped-mass/rotational-spring chain in inertial frame, prescribed hub angle
import numpy as np
from scipy.integrate import solve_ivp
L=10.;EI=1.4e4;rA=1.2;Ts=15.
def setup(N):
    h=L/N; m=np.full(N,rA*h); m[-1]=rA*h/2
    mu=np.array([[m[max(i,k):].sum() for k in range(N)] for i in range(N)])
    k=np.full(N,EI/h); k[0]=2*EI/h   # root hinge at half-element (clamp)
    return h,m,mu,k
def th(t,Os): return Os/Ts*(t*t/2+(Ts/(2*np.pi))**2*(np.cos(2*np.pi*t/Ts)-1)) if t<=Ts else Os*(t-Ts/2)
def run(Os,N=40,tf=20.):
    h,m,mu,k=setup(N)
    def rhs(t,y):
        p=y[:N]; pd=y[N:]
        d=p[:,None]-p[None,:]
        M=h*h*mu*np.cos(d)
        c=h*h*(mu*np.sin(d))@(pd**2)
        rel=np.diff(np.concatenate([[th(t,Os)],p]))
        tau=k*rel; dV=tau.copy(); dV[:-1]-=tau[1:]
        return np.concatenate([pd,np.linalg.solve(M,-c-dV)])
    te=np.linspace(0,tf,4001)
    s=solve_ivp(rhs,(0,tf),np.zeros(2*N),t_eval=te,method='DOP853',rtol=1e-9,atol=1e-11)
    p=s.y[:N]; X=h*np.cos(p).sum(0); Y=h*np.sin(p).sum(0)
    T=np.array([th(t,Os) for t in s.t])
    v=-np.sin(T)*X+np.cos(T)*Y; u=np.cos(T)*X+np.sin(T)*Y-L
    return s.t,v,u
import sys
N=int(sys.argv[1]) if len(sys.argv)>1 else 40
for Os in [4,6,10]:
    t,v,u=run(Os,N)
    i=np.argmin(v); post=t>Ts
    print(f"chain N={N} Os={Os}: min v={v[i]:+.4f} at t={t[i]:.3f}; v(15)={np.interp(15,t,v):+.4f}; |v| after Ts max={np.abs(v[post]).max():.4f}; u_tip at min={u[i]:+.4f}")

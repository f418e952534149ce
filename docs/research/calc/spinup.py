import numpy as np, sys
from scipy.integrate import solve_ivp
sys.path.insert(0,'/tmp/research/calc')
from rotbeam import mats
L=10.; EI=1.4e4; rA=1.2; Ts=15.
K,M,G,F=mats(20,L,EI,rA)
Mi=np.linalg.inv(M); n=K.shape[0]
def Om(t,Os): return Os/Ts*(t-Ts/(2*np.pi)*np.sin(2*np.pi*t/Ts)) if t<=Ts else Os
def Omd(t,Os): return Os/Ts*(1-np.cos(2*np.pi*t/Ts)) if t<=Ts else 0.
def run(Os,stiff=True,tf=30.):
    def rhs(t,y):
        q=y[:n]; qd=y[n:]; O=Om(t,Os)
        Kt=K+O*O*((G if stiff else 0)-M)
        return np.concatenate([qd, Mi@(-Kt@q - Omd(t,Os)*F)])
    te=np.linspace(0,tf,30001)
    s=solve_ivp(rhs,(0,tf),np.zeros(2*n),t_eval=te,method='DOP853',rtol=1e-10,atol=1e-12,max_step=0.01)
    return s.t, s.y[n-2]  # tip transverse displacement (last node v)
for Os in [2,4,6,10]:
    for stiff in [True,False]:
        t,v=run(Os,stiff)
        i=np.argmin(v); j=np.argmax(np.abs(v))
        post=(t>Ts)&(t<=30)
        print(f"Os={Os:4.1f} stiff={stiff!s:5}: min v_tip={v[i]:+.5f} m at t={t[i]:.3f} s; v(Ts)={np.interp(Ts,t,v):+.5f}; after Ts: max={v[post].max():+.5f} min={v[post].min():+.5f} ; v(30)={v[-1]:+.4e}")
        for tt in [2.5,5,7.5,10,12.5,15,20]:
            pass
        if stiff: print("   samples t,v:", " ".join(f"({tt},{np.interp(tt,t,v):+.4f})" for tt in [2.5,5,6,7,7.5,8,9,10,12.5,15]))

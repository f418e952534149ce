import numpy as np, scipy.linalg as sl
def mats(ne, L=1.0, EI=1.0, rA=1.0):
    h=L/ne; n=2*(ne+1)
    K=np.zeros((n,n)); M=np.zeros((n,n)); G=np.zeros((n,n)); F=np.zeros(n)
    ke=EI/h**3*np.array([[12,6*h,-12,6*h],[6*h,4*h*h,-6*h,2*h*h],[-12,-6*h,12,-6*h],[6*h,2*h*h,-6*h,4*h*h]])
    me=rA*h/420*np.array([[156,22*h,54,-13*h],[22*h,4*h*h,13*h,-3*h*h],[54,13*h,156,-22*h],[-13*h,-3*h*h,-22*h,4*h*h]])
    # gauss for geometric stiffness with T(x)=rA*(L^2-x^2)/2 (per Omega^2), and load x
    gp,gw=np.polynomial.legendre.leggauss(6)
    for e in range(ne):
        idx=slice(2*e,2*e+4); x0=e*h
        K[idx,idx]+=ke; M[idx,idx]+=me
        for xi,w in zip(gp,gw):
            s=(xi+1)/2; x=x0+s*h
            N=np.array([1-3*s*s+2*s**3, h*(s-2*s*s+s**3), 3*s*s-2*s**3, h*(-s*s+s**3)])
            dN=np.array([-6*s+6*s*s, h*(1-4*s+3*s*s), 6*s-6*s*s, h*(-2*s+3*s*s)])/h
            T=rA*(L*L-x*x)/2
            G[idx,idx]+=w*h/2*T*np.outer(dN,dN)
            F[idx]+=w*h/2*rA*x*N
    f=slice(2,n)
    return K[f,f],M[f,f],G[f,f],F[f]
if __name__=="__main__":
    K,M,G,F=mats(40)
    print("gamma | flap1 flap2 flap3 | chord1 chord2 chord3   (omega/sqrt(EI/rhoA L^4))")
    for g in [0,1,2,3,4,5,6,7,8,9,10,12]:
        wf=np.sqrt(np.sort(sl.eigh(K+g*g*G,M,eigvals_only=True)))[:3]
        ev=np.sort(sl.eigh(K+g*g*G-g*g*M,M,eigvals_only=True))[:3]
        wc=np.sqrt(ev.astype(complex))
        print(f"{g:5.1f} | {wf[0]:8.4f} {wf[1]:8.4f} {wf[2]:8.4f} | {wc[0].real:8.4f} {wc[1].real:8.4f} {wc[2].real:8.4f}   check sqrt(f^2-g^2): {np.sqrt(max(wf[0]**2-g*g,0)):.4f}")

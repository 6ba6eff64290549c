C     Robertson's kinetics (Hairer & Wanner II, IV.1) with RADAU5:
C     y1' = -0.04 y1 + 1e4 y2 y3, y3' = 3e7 y2**2, y2' = -y1' - y3',
C     y(0) = (1, 0, 0), t in [0, 40], per-component tolerances (ITOL=1).
C     robertson.f is this program with taylorode: only the CALL
C     statement differs.
      PROGRAM ROBER
      IMPLICIT DOUBLE PRECISION (A-H,O-Z)
      PARAMETER (ND=3,LWORK=4*ND*ND+12*ND+20,LIWORK=3*ND+20)
      DIMENSION Y(ND),WORK(LWORK),IWORK(LIWORK),RPAR(3),IPAR(1)
      DIMENSION RTOL(ND),ATOL(ND)
      EXTERNAL FROBER,JROBER,DUMMAS,SOLOUT
      N=ND
      RPAR(1)=0.04D0
      RPAR(2)=3.0D7
      RPAR(3)=1.0D4
      IJAC=1
      MLJAC=N
      MUJAC=0
      IMAS=0
      MLMAS=N
      MUMAS=0
      IOUT=0
      X=0.0D0
      Y(1)=1.0D0
      Y(2)=0.0D0
      Y(3)=0.0D0
      XEND=40.0D0
      ITOL=1
      DO 10 I=1,N
         RTOL(I)=1.0D-8
         ATOL(I)=1.0D-12
   10 CONTINUE
      ATOL(2)=1.0D-16
      H=1.0D-6
      DO 20 I=1,20
         IWORK(I)=0
         WORK(I)=0.0D0
   20 CONTINUE
      CALL TAYLORODE('radau5',N,FROBER,X,Y,XEND,H,RTOL,ATOL,ITOL,
     &            JROBER,IJAC,MLJAC,MUJAC,DUMMAS,IMAS,MLMAS,MUMAS,
     &            SOLOUT,IOUT,WORK,LWORK,IWORK,LIWORK,RPAR,IPAR,IDID)
      WRITE (6,90) X,(Y(I),I=1,N)
      WRITE (6,91) IDID,(IWORK(I),I=14,20)
   90 FORMAT(' X =',F8.3,'  Y =',3E24.16)
   91 FORMAT(' IDID =',I3,'  NFCN NJAC NSTEP NACCPT NREJCT NDEC NSOL =',
     &       7I8)
      END

      SUBROUTINE FROBER(N,X,Y,F,RPAR,IPAR)
      IMPLICIT DOUBLE PRECISION (A-H,O-Z)
      DIMENSION Y(N),F(N),RPAR(*),IPAR(*)
      F(1)=-RPAR(1)*Y(1)+RPAR(3)*Y(2)*Y(3)
      F(3)=RPAR(2)*Y(2)**2
      F(2)=-F(1)-F(3)
      RETURN
      END

      SUBROUTINE JROBER(N,X,Y,DFY,LDFY,RPAR,IPAR)
      IMPLICIT DOUBLE PRECISION (A-H,O-Z)
      DIMENSION Y(N),DFY(LDFY,N),RPAR(*),IPAR(*)
      DFY(1,1)=-RPAR(1)
      DFY(1,2)=RPAR(3)*Y(3)
      DFY(1,3)=RPAR(3)*Y(2)
      DFY(3,1)=0.0D0
      DFY(3,2)=2.0D0*RPAR(2)*Y(2)
      DFY(3,3)=0.0D0
      DFY(2,1)=-DFY(1,1)-DFY(3,1)
      DFY(2,2)=-DFY(1,2)-DFY(3,2)
      DFY(2,3)=-DFY(1,3)-DFY(3,3)
      RETURN
      END

      SUBROUTINE DUMMAS(N,AM,LMAS,RPAR,IPAR)
      IMPLICIT DOUBLE PRECISION (A-H,O-Z)
      DIMENSION AM(LMAS,N),RPAR(*),IPAR(*)
      RETURN
      END

      SUBROUTINE SOLOUT(NR,XOLD,X,Y,CONT,LRC,N,RPAR,IPAR,IRTRN)
      IMPLICIT DOUBLE PRECISION (A-H,O-Z)
      DIMENSION Y(N),CONT(LRC),RPAR(*),IPAR(*)
      RETURN
      END

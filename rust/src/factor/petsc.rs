//! The part of PETSc's C API the MUMPS backend calls, reached at run time in the library the
//! process has loaded (petsc4py's), so that neither the build nor the faer path needs PETSc.
//!
//! Types as PETSc 3.18 declares them for Debian's real, 32-bit-index build
//! (`petscconf.h`: PETSC_SIZEOF_INT 4, PETSC_USE_REAL_DOUBLE): PetscInt = i32, PetscScalar =
//! f64, PetscErrorCode, PetscBool and every enum = C int; objects and MPI_Comm (OpenMPI) are
//! pointers.

use crate::error::Result;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::sync::OnceLock;

pub type PetscInt = i32;
pub type ErrorCode = c_int;
/// Any PETSc object handle (Mat, Vec, VecScatter), and an MPI communicator.
pub type Handle = *mut c_void;

/// The library petsc4py loads (Debian's python3-petsc4py 3.18), by its file name.
const LIBRARY: &str = "libpetsc_real.so.3.18";

// PETSc's enum values (petscmat.h, petscvec.h, petscsystypes.h).
pub const MAT_FACTOR_CHOLESKY: c_int = 2;
pub const MAT_FINAL_ASSEMBLY: c_int = 0;
pub const MAT_SPD: c_int = 15;
pub const INSERT_VALUES: c_int = 1;
pub const SCATTER_FORWARD: c_int = 0;
pub const PETSC_TRUE: c_int = 1;
pub const PETSC_DECIDE: PetscInt = -1;
/// MatFactorError: the numeric factorization met a zero (or, SPD, a non-positive) pivot.
pub const MAT_FACTOR_NUMERIC_ZEROPIVOT: c_int = 2;
/// `MatFactorInfo`: eleven PetscReal fields, set by `MatFactorInfoInitialize`.
pub type FactorInfo = [f64; 11];

/// Declares the table of C functions, each looked up by its own name.
macro_rules! api {
    ($($name:ident: fn($($arg:ty),*);)*) => {
        #[allow(non_snake_case)]
        pub struct Api {
            $(pub $name: unsafe extern "C" fn($($arg),*) -> ErrorCode,)*
            /// PETSC_COMM_WORLD (valid once PETSc is initialised).
            comm_world: *const Handle,
            /// PetscIgnoreErrorHandler, to push as the handler (`quietly`).
            ignore_errors: *mut c_void,
        }

        impl Api {
            /// Every function from the library at `handle` (dlopen's).
            unsafe fn load(handle: *mut c_void) -> std::result::Result<Self, String> {
                Ok(Api {
                    $($name: std::mem::transmute::<*mut c_void, unsafe extern "C" fn($($arg),*) -> ErrorCode>(symbol(handle, stringify!($name))?),)*
                    comm_world: symbol(handle, "PETSC_COMM_WORLD")? as *const Handle,
                    ignore_errors: symbol(handle, "PetscIgnoreErrorHandler")?,
                })
            }
        }
    };
}

api! {
    PetscInitialized: fn(*mut c_int);
    PetscInitializeNoArguments: fn();
    PetscPushErrorHandler: fn(*mut c_void, *mut c_void);
    PetscPopErrorHandler: fn();
    MPI_Comm_rank: fn(Handle, *mut c_int);
    MPI_Comm_size: fn(Handle, *mut c_int);
    MPI_Abort: fn(Handle, c_int);
    MatCreateSBAIJ: fn(Handle, PetscInt, PetscInt, PetscInt, PetscInt, PetscInt, PetscInt, *const PetscInt, PetscInt, *const PetscInt, *mut Handle);
    MatSetOption: fn(Handle, c_int, c_int);
    MatSetValues: fn(Handle, PetscInt, *const PetscInt, PetscInt, *const PetscInt, *const f64, c_int);
    MatAssemblyBegin: fn(Handle, c_int);
    MatAssemblyEnd: fn(Handle, c_int);
    MatGetFactor: fn(Handle, *const c_char, c_int, *mut Handle);
    MatFactorInfoInitialize: fn(*mut FactorInfo);
    MatCholeskyFactorSymbolic: fn(Handle, Handle, Handle, *const FactorInfo);
    MatCholeskyFactorNumeric: fn(Handle, Handle, *const FactorInfo);
    MatFactorGetError: fn(Handle, *mut c_int);
    MatMumpsGetInfog: fn(Handle, PetscInt, *mut PetscInt);
    MatMumpsSetIcntl: fn(Handle, PetscInt, PetscInt);
    MatMumpsGetInverse: fn(Handle, Handle);
    MatCreateAIJ: fn(Handle, PetscInt, PetscInt, PetscInt, PetscInt, PetscInt, *const PetscInt, PetscInt, *const PetscInt, *mut Handle);
    MatCreateTranspose: fn(Handle, *mut Handle);
    MatGetValues: fn(Handle, PetscInt, *const PetscInt, PetscInt, *const PetscInt, *mut f64);
    VecCreateMPI: fn(Handle, PetscInt, PetscInt, *mut Handle);
    MatCreateVecs: fn(Handle, *mut Handle, *mut Handle);
    MatSolve: fn(Handle, Handle, Handle);
    MatMatSolve: fn(Handle, Handle, Handle);
    MatCreateDense: fn(Handle, PetscInt, PetscInt, PetscInt, PetscInt, *mut f64, *mut Handle);
    MatDenseGetArray: fn(Handle, *mut *mut f64);
    MatDenseRestoreArray: fn(Handle, *mut *mut f64);
    MatDenseGetColumnVecRead: fn(Handle, PetscInt, *mut Handle);
    MatDenseRestoreColumnVecRead: fn(Handle, PetscInt, *mut Handle);
    MatDestroy: fn(*mut Handle);
    VecGetArray: fn(Handle, *mut *mut f64);
    VecRestoreArray: fn(Handle, *mut *mut f64);
    VecGetArrayRead: fn(Handle, *mut *const f64);
    VecRestoreArrayRead: fn(Handle, *mut *const f64);
    VecScatterCreateToAll: fn(Handle, *mut Handle, *mut Handle);
    VecScatterBegin: fn(Handle, Handle, Handle, c_int, c_int);
    VecScatterEnd: fn(Handle, Handle, Handle, c_int, c_int);
    VecScatterDestroy: fn(*mut Handle);
    VecDestroy: fn(*mut Handle);
}

// The table holds plain function pointers into a library that stays loaded.
unsafe impl Send for Api {}
unsafe impl Sync for Api {}

unsafe fn symbol(handle: *mut c_void, name: &str) -> std::result::Result<*mut c_void, String> {
    let c = CString::new(name).expect("a symbol name has no NUL");
    let p = libc::dlsym(handle, c.as_ptr());
    if p.is_null() {
        return Err(format!("{LIBRARY} has no symbol {name}"));
    }
    Ok(p)
}

/// The PETSc library already in the process (petsc4py's, whatever its path), else Debian's by
/// its file name.
fn library_path() -> String {
    let maps = std::fs::read_to_string("/proc/self/maps").unwrap_or_default();
    maps.lines()
        .filter_map(|l| l.split_whitespace().nth(5))
        .find(|p| p.contains("/libpetsc") && p.contains(".so"))
        .unwrap_or(LIBRARY)
        .to_string()
}

/// The API, loaded and PETSc initialised once per process (by petsc4py under `slipstep run`;
/// here when the engine is used alone, on one rank unless under `mpirun`).
pub fn api() -> Result<&'static Api> {
    static API: OnceLock<std::result::Result<Api, String>> = OnceLock::new();
    let loaded = API.get_or_init(|| unsafe {
        let path = library_path();
        let c = CString::new(path.clone()).map_err(|e| e.to_string())?;
        let handle = libc::dlopen(c.as_ptr(), libc::RTLD_NOW | libc::RTLD_GLOBAL);
        if handle.is_null() {
            let why = CStr::from_ptr(libc::dlerror()).to_string_lossy().into_owned();
            return Err(format!("could not load PETSc ({why})"));
        }
        let api = Api::load(handle)?;
        let mut initialised = 0;
        (api.PetscInitialized)(&mut initialised);
        if initialised == 0 && (api.PetscInitializeNoArguments)() != 0 {
            return Err("PetscInitialize failed".into());
        }
        Ok(api)
    });
    loaded.as_ref().map_err(|why| crate::fail!(Input, "options.factorization = \"mumps\" needs PETSc with MUMPS (Debian: apt install python3-petsc4py): {why}; or use factorization = \"faer\""))
}

impl Api {
    /// PETSC_COMM_WORLD.
    pub fn comm(&self) -> Handle {
        unsafe { *self.comm_world }
    }

    /// (this rank, number of ranks) in PETSC_COMM_WORLD.
    pub fn rank_and_size(&self) -> (usize, usize) {
        let (mut rank, mut size) = (0, 1);
        unsafe {
            (self.MPI_Comm_rank)(self.comm(), &mut rank);
            (self.MPI_Comm_size)(self.comm(), &mut size);
        }
        (rank as usize, size as usize)
    }

    /// A PETSc call's error code as an error naming the call.
    pub fn check(&self, code: ErrorCode, call: &str) -> Result<()> {
        if code == 0 {
            return Ok(());
        }
        Err(crate::fail!(Internal, "PETSc's {call} failed (error code {code}): run with factorization = \"faer\", or see PETSc's error codes"))
    }

    /// A call the run cannot go on without once the factor exists (a solve: collective on
    /// every rank): one line on stderr and MPI_Abort, which ends every rank (a rank that
    /// returned alone would leave the others waiting in the next collective call).
    pub fn must(&self, code: ErrorCode, call: &str) {
        if code != 0 {
            eprintln!("slipstep: error: PETSc's {call} failed (error code {code}) inside the MUMPS factorization's solve; every rank stops");
            unsafe { (self.MPI_Abort)(self.comm(), 1) };
            std::process::exit(1);
        }
    }

    /// Run `f` with PETSc's error handler set to ignore (errors come back as codes, no trace
    /// printed), then restore it.
    pub fn quietly<R>(&self, f: impl FnOnce() -> R) -> R {
        unsafe { (self.PetscPushErrorHandler)(self.ignore_errors, std::ptr::null_mut()) };
        let r = f();
        unsafe { (self.PetscPopErrorHandler)() };
        r
    }
}

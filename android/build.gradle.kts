// stridekit Android library (AAR): the Rust library for four ABIs (cargo-ndk), Kotlin
// bindings generated from the built arm64 library (uniffi-bindgen with
// uniffi-android.toml), the adapters in src/main/kotlin, and JNA (AAR) for the bindings.
//
//   ./gradlew assembleRelease      -> build/outputs/aar/stridekit-android-release.aar
//   ./gradlew publishReleasePublicationToLocalRepository
//                                  -> ../target/maven/io/stridekit/stridekit-android/0.1.0/
//                                     (AAR + POM with JNA, coroutines, androidx.annotation)
//
// Prerequisites and what was verified: README.md.

import org.jetbrains.kotlin.gradle.dsl.JvmTarget

plugins {
    id("com.android.library") version "8.7.3"
    id("org.jetbrains.kotlin.android") version "2.3.20"
    `maven-publish`
}

group = "io.stridekit"
version = "0.1.0"

val workspaceDir: File = rootDir.parentFile
// "release" (default) or "dev" (-Pstridekit.cargoProfile=dev: quick, large libraries).
val cargoProfile: String = (findProperty("stridekit.cargoProfile") as String?) ?: "release"
val cargoProfileDir: String = if (cargoProfile == "release") "release" else "debug"
val cargoTargetDir: File = System.getenv("CARGO_TARGET_DIR")?.let(::File) ?: workspaceDir.resolve("target")
val minSdkVersion = 24
// ABI (jniLibs folder) -> Rust target triple.
val abis = linkedMapOf(
    "arm64-v8a" to "aarch64-linux-android",
    "armeabi-v7a" to "armv7-linux-androideabi",
    "x86_64" to "x86_64-linux-android",
    "x86" to "i686-linux-android",
)
val jniLibsDir: File = layout.projectDirectory.dir("src/main/jniLibs").asFile
val generatedKotlinDir = layout.buildDirectory.dir("generated/uniffi/kotlin")
val bindgenLibrary: File = cargoTargetDir.resolve("aarch64-linux-android/$cargoProfileDir/libstridekit.so")

android {
    namespace = "io.stridekit"
    compileSdk = 35

    defaultConfig {
        minSdk = minSdkVersion
        consumerProguardFiles("consumer-rules.pro")
        ndk { abiFilters += abis.keys }
    }

    buildTypes {
        release { isMinifyEnabled = false }
    }

    compileOptions {
        sourceCompatibility = JavaVersion.VERSION_17
        targetCompatibility = JavaVersion.VERSION_17
    }

    sourceSets["main"].apply {
        jniLibs.srcDir(jniLibsDir)
        java.srcDir(generatedKotlinDir)
    }

    // The release variant as a Maven publication (AAR + POM carrying the dependencies
    // below), so an app depends on coordinates instead of a bare files(…aar).
    // withJavadocJar: AGP runs Dokka on the Kotlin sources (the generated bindings'
    // KDoc and the adapters') into the publication's -javadoc.jar.
    publishing {
        singleVariant("release") {
            withSourcesJar()
            withJavadocJar()
        }
    }

    packaging {
        // Keep the libraries as cargo built them (debug info already stripped; the
        // symbols stay, so uniffi-bindgen can read the AAR's own libraries too).
        jniLibs.keepDebugSymbols += "**/libstridekit.so"
    }
}

kotlin {
    compilerOptions { jvmTarget.set(JvmTarget.JVM_17) }
}

dependencies {
    // The generated bindings call the library through JNA (direct mapping); the @aar
    // artifact carries libjnidispatch.so for every ABI.
    implementation("net.java.dev.jna:jna:5.17.0@aar")
    // android = true in uniffi-android.toml: @RequiresApi in the generated code.
    implementation("androidx.annotation:annotation:1.9.1")
    // The Flow of estimates (same version as ../tests/pom.xml).
    api("org.jetbrains.kotlinx:kotlinx-coroutines-core:1.10.2")
}

// 1. The Rust library for the four ABIs into src/main/jniLibs/<abi>/libstridekit.so.
val cargoNdk by tasks.registering(Exec::class) {
    group = "stridekit"
    description = "cargo ndk: libstridekit.so for ${abis.keys.joinToString()} (profile $cargoProfile)"
    workingDir = workspaceDir
    val args = mutableListOf("cargo", "ndk")
    abis.keys.forEach { args += listOf("-t", it) }
    args += listOf("--platform", minSdkVersion.toString(), "-o", jniLibsDir.path)
    args += listOf("build", "-p", "stridekit", "--lib", "--locked")
    if (cargoProfile == "release") args += "--release"
    commandLine(args)
    // cargo decides what is up to date; always ask it.
    outputs.upToDateWhen { false }
    outputs.dir(jniLibsDir)
}

// 2. The host uniffi-bindgen (dev profile, its own cargo invocation: building it with
//    the library would rebuild the library with uniffi's CLI feature).
val bindgenBinary: File = cargoTargetDir.resolve("debug/uniffi-bindgen")
val buildBindgen by tasks.registering(Exec::class) {
    group = "stridekit"
    description = "cargo build the host uniffi-bindgen"
    workingDir = workspaceDir
    commandLine("cargo", "build", "-p", "stridekit", "--features", "cli", "--bin", "uniffi-bindgen", "--locked")
    outputs.upToDateWhen { false }
}

// 3. Kotlin bindings from the arm64 library just built (the same metadata is in every
//    ABI's library), with the Android config: android = true, omit_checksums = true.
val generateBindings by tasks.registering(Exec::class) {
    group = "stridekit"
    description = "uniffi-bindgen: Kotlin bindings from $bindgenLibrary"
    dependsOn(cargoNdk, buildBindgen)
    workingDir = workspaceDir
    val out = generatedKotlinDir.get().asFile
    doFirst {
        check(bindgenLibrary.isFile) { "$bindgenLibrary not built (cargoNdk)" }
        out.deleteRecursively()
    }
    commandLine(
        bindgenBinary.path, "generate", bindgenLibrary.path,
        "--language", "kotlin",
        "--config", layout.projectDirectory.file("uniffi-android.toml").asFile.path,
        "--out-dir", out.path,
        "--no-format",
    )
    // Exception messages read the SDK's Display text instead of uniffi's field dump
    // (the rewrite bindings/kotlin-messages.py makes for the JVM bindings).
    doLast {
        val kt = out.resolve("io/stridekit/stridekit.kt")
        val getter = Regex("override val message\\n(\\s+)get\\(\\) = \"[^\"\\n]*\"")
        val text = kt.readText()
        check(getter.containsMatchIn(text)) { "no exception message getter in $kt (generated code changed?)" }
        kt.writeText(getter.replace(text, "override val message: String\n$1get() = toString()"))
    }
    outputs.dir(out)
}

// 1b. Google Play: every LOAD segment of every ABI's library aligned to 16 KB
//     (bindings/build.rs links with -z max-page-size=16384; NDK r27c defaults to 4 KB).
val checkAlignment by tasks.registering(Exec::class) {
    group = "stridekit"
    description = "every jniLibs/<abi>/libstridekit.so has its LOAD segments aligned to 16 KB"
    dependsOn(cargoNdk)
    workingDir = workspaceDir
    commandLine("python3", "android/check-alignment.py", "--jnilibs", jniLibsDir.path)
}

// 4. The same checks scripts/test runs on the host bindings, on these.
val checkBindings by tasks.registering(Exec::class) {
    group = "stridekit"
    description = "the generated Kotlin has the Android cleaner and no checksum check"
    dependsOn(generateBindings, checkAlignment)
    workingDir = workspaceDir
    commandLine(
        "sh", "-c",
        "grep -q '^import android.os.Build' \"\$0\" && ! grep -q 'uniffiCheckApiChecksums' \"\$0\" && " +
            "for abi in ${abis.keys.joinToString(" ")}; do test -s \"\$1/\$abi/libstridekit.so\" || { echo \"missing \$abi\"; exit 1; }; done",
        generatedKotlinDir.get().asFile.resolve("io/stridekit/stridekit.kt").path,
        jniLibsDir.path,
    )
}

tasks.named("preBuild") { dependsOn(checkBindings) }

tasks.named<Delete>("clean") { delete(jniLibsDir) }

// 5. Maven publication: io.stridekit:stridekit-android:<version> into
//    <repository>/target/maven (a local repository an app adds with maven { url = … }).
afterEvaluate {
    publishing {
        publications {
            register<MavenPublication>("release") {
                from(components["release"])
                artifactId = "stridekit-android"
                pom {
                    name.set("stridekit for Android")
                    description.set("Running pace, orientation and pedestrian navigation from phone sensors")
                }
            }
        }
        repositories {
            maven {
                name = "local"
                url = uri(workspaceDir.resolve("target/maven"))
            }
        }
    }
}

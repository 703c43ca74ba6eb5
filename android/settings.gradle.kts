// The stridekit Android library, a Gradle build of its own (run from this folder:
// ./gradlew assembleRelease, see README.md). The Rust workspace is the parent folder.
pluginManagement {
    repositories {
        google()
        mavenCentral()
        gradlePluginPortal()
    }
}

dependencyResolutionManagement {
    repositoriesMode.set(RepositoriesMode.FAIL_ON_PROJECT_REPOS)
    repositories {
        google()
        mavenCentral()
    }
}

rootProject.name = "stridekit-android"

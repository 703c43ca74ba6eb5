package androidx.annotation
// Stand-in for androidx.annotation.RequiresApi (Google Maven only), same shape.
@Retention(AnnotationRetention.BINARY)
@Target(AnnotationTarget.CLASS, AnnotationTarget.FUNCTION, AnnotationTarget.CONSTRUCTOR, AnnotationTarget.FIELD, AnnotationTarget.PROPERTY_GETTER, AnnotationTarget.PROPERTY_SETTER, AnnotationTarget.FILE)
annotation class RequiresApi(val value: Int = 1, val api: Int = 1)
